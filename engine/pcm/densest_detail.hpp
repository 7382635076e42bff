// The densest selector's product with the 0/1 adjacency in dense storage (densest.cpp), exposed for its test.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "pcm/consistency_graph.hpp"

namespace keel::pcm::detail {

// The adjacency A of a graph as byte columns: byte c of column j holds A(8c … 8c+7, j), bit k for row 8c + k
// (A is symmetric, so this is byte c of the graph's bit row j), stored chunk-major so that one chunk of rows
// reads the bytes of successive columns from consecutive addresses. n²/8 bytes, where a dense matrix of
// doubles takes 8n².
//
// product() computes out = A u summed row by row in a fixed order: over `columns` (ascending) in blocks of
// `block` consecutive column indices, each block summed from zero in column order and then added to the row's
// running sum, which starts at zero. Entries A(i, j) = 0 and columns with u_j = 0 add exact zeros, so they
// are skipped without changing a bit of the result (u >= 0, so no −0.0 can arise). With block = 16 for 128 <=
// n < 4000 (4 above, n below 128) and all columns this is the order of Eigen 3.4's column-major matrix-vector
// product, and with one block over the support it is the order of Σ_j u_j A(:, j) accumulated column by
// column: the two dense products the selector used before, bit for bit (densest_test.cpp).
class ByteAdjacency {
 public:
  ByteAdjacency() = default;
  explicit ByteAdjacency(const ConsistencyGraph& g);

  int size() const { return n_; }
  // The block size of Eigen's column-major product for an n x n matrix (see above).
  static int eigen_block(int n);

  // The instructions the sums run on: all give the same bits (one order of additions); `automatic` takes the
  // widest this CPU has. available() says whether the CPU has a kernel's instructions.
  enum class Kernel { automatic, generic, avx2, avx512 };
  static bool available(Kernel kernel);
  static Kernel best();  // what `automatic` takes

  // out[0 … n) = A u over the columns listed (ascending; the others must have u_j = 0); u and out hold n
  // doubles and must not overlap. Throws std::invalid_argument for block < 1 or a kernel this CPU lacks.
  // Not thread-safe on one object (a scratch list of block boundaries).
  void product(const double* u, std::span<const int> columns, int block, double* out,
               Kernel kernel = Kernel::automatic) const;

 private:
  int n_ = 0;
  int chunks_ = 0;
  std::vector<std::uint8_t> bytes_;   // bytes_[c * n + j]: byte c of column j
  mutable std::vector<int> segment_;  // end of each block's run in `columns`
};

}  // namespace keel::pcm::detail
