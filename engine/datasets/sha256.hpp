// keel::graph — SHA-256 (FIPS 180-4), small and dependency-free, for verifying dataset files against the
// manifest.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace keel::datasets {

class Sha256 {
 public:
  Sha256();
  void update(const void* data, std::size_t size);
  void update(std::string_view bytes) { update(bytes.data(), bytes.size()); }
  std::array<std::uint8_t, 32> digest();  // finishes the hash; call once
  std::string hex_digest();               // lower-case hex of digest()

 private:
  void block(const std::uint8_t* p);
  std::array<std::uint32_t, 8> h_;
  std::array<std::uint8_t, 64> buf_{};
  std::size_t buf_len_ = 0;
  std::uint64_t total_ = 0;
};

std::string sha256_hex(std::string_view bytes);
/// Streams the file; throws std::runtime_error when it cannot be read.
std::string sha256_file(const std::filesystem::path& file);

}  // namespace keel::datasets
