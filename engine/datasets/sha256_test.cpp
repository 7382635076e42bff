// SHA-256 against the FIPS 180-4 / NIST example vectors, and streaming in odd-sized pieces.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "datasets/sha256.hpp"

using namespace keel::datasets;

TEST_CASE("sha256 known vectors") {
  CHECK(sha256_hex("") == "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  CHECK(sha256_hex("abc") == "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  CHECK(sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq") ==
        "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  CHECK(sha256_hex(
            "abcdefghbcdefghicdefghijdefghijkefghijklfghijklmghijklmnhijklmnoijklmnopjklmnopqklmnopqrlmnopqrs"
            "mnopqrstnopqrstu") == "cf5b16a778af8380036ce59e7b0492370b249b11e8f07a51afac45037afee9d1");
  CHECK(sha256_hex(std::string(1000000, 'a')) ==
        "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
  // Lengths around the padding boundary (55, 56, 63, 64 bytes), checked against the one-shot digest when
  // streamed.
  for (std::size_t n : {55u, 56u, 57u, 63u, 64u, 65u, 119u, 120u, 1000u}) {
    const std::string s(n, 'x');
    Sha256 h;
    for (std::size_t k = 0; k < n; k += 7) h.update(std::string_view(s).substr(k, 7));
    CHECK(h.hex_digest() == sha256_hex(s));
  }
  CHECK(sha256_hex(std::string(55, 'x')) ==
        "d5e285683cd4efc02d021a5c62014694958901005d6f71e89e0989fac77e4072");
}

TEST_CASE("sha256_file streams a file") {
  const auto path = std::filesystem::temp_directory_path() / "keel_sha256_test.bin";
  {
    std::ofstream out(path, std::ios::binary);
    const std::string block(100000, 'a');
    for (int k = 0; k < 10; ++k) out << block;
  }
  CHECK(sha256_file(path) == "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
  std::filesystem::remove(path);
  CHECK_THROWS(sha256_file(path));
}
