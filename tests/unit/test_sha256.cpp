// SHA-256 (core/sha256.hpp) against the FIPS 180-2 test vectors (Appendix B).
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include "pheromesh/core/sha256.hpp"

using namespace pheromesh::core;

TEST(Sha256, OneBlockMessageAbcMatchesFips180) {
  EXPECT_EQ(sha256_hex(std::string_view("abc")), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
}

TEST(Sha256, MultiBlockMessageMatchesFips180) {
  EXPECT_EQ(sha256_hex(std::string_view("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq")),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
}

TEST(Sha256, AMillionTimesAMatchesFips180AndAFileHashesLikeItsBytes) {
  const std::string a(1000000, 'a');
  const std::string want = "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0";
  EXPECT_EQ(sha256_hex(std::string_view(a)), want);
  const auto path = std::filesystem::temp_directory_path() / ("phm-sha256-" + std::to_string(::getpid()));
  std::FILE* f = std::fopen(path.c_str(), "wb");
  ASSERT_NE(f, nullptr);
  std::fwrite(a.data(), 1, a.size(), f);
  std::fclose(f);
  auto got = sha256_file_hex(path.string());
  std::filesystem::remove(path);
  ASSERT_TRUE(got.ok()) << got.error().message;
  EXPECT_EQ(got.value(), want);
}

TEST(Sha256, EmptyMessageAndAMissingFileNamed) {
  EXPECT_EQ(sha256_hex(std::string_view()), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  auto missing = sha256_file_hex("/nonexistent/phm-file");
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().message.find("/nonexistent/phm-file: cannot read"), std::string::npos);
  EXPECT_TRUE(is_sha256_hex(std::string(64, 'A')));
  EXPECT_FALSE(is_sha256_hex(std::string(63, 'a')));
  EXPECT_FALSE(is_sha256_hex(std::string(63, 'a') + "g"));
}
