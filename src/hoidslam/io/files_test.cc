#include "hoidslam/io/files.h"

#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "hoidslam/core/error.h"
#include "support/temp_dir.h"

namespace hoidslam::io {
namespace {

using ::testing::HasSubstr;

// The message of the InputError ReadBinaryFile throws for `path`, or "" when it throws none.
std::string ReadError(const std::filesystem::path& path) {
  try {
    ReadBinaryFile(path, "map file");
  } catch (const core::InputError& error) {
    return error.what();
  }
  return "";
}

TEST(ReadBinaryFile, ReadsEveryByte) {
  testing::TempDir dir;
  std::vector<std::uint8_t> bytes;
  for (int i = 0; i < 3 * 256; ++i) bytes.push_back(static_cast<std::uint8_t>(i % 256));  // NUL, CR, LF, 0x1A, 0xFF
  {
    std::ofstream file(dir / "all.bin", std::ios::binary);
    file.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  }
  EXPECT_EQ(ReadBinaryFile(dir / "all.bin", "map file"), bytes);
  { std::ofstream empty(dir / "empty.bin", std::ios::binary); }
  EXPECT_TRUE(ReadBinaryFile(dir / "empty.bin", "map file").empty());
}

TEST(FileSha256, IsWhatSha256sumPrints) {
  testing::TempDir dir;
  std::ofstream(dir / "abc.txt", std::ios::binary) << "abc";
  { std::ofstream empty(dir / "empty.bin", std::ios::binary); }
  // The test vectors of FIPS 180-2.
  EXPECT_EQ(FileSha256(dir / "abc.txt", "model"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(FileSha256(dir / "empty.bin", "model"), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_THROW(FileSha256(dir / "absent.onnx", "model"), core::InputError);
}

TEST(ReadBinaryFile, AMissingFileOrAFolderIsAnErrorNamingIt) {
  testing::TempDir dir;
  const std::filesystem::path missing = dir / "absent.hmap";
  EXPECT_THROW(ReadBinaryFile(missing, "map file"), core::InputError);
  EXPECT_THAT(ReadError(missing), HasSubstr(missing.string() + ": map file does not exist or is not a file"));
  EXPECT_THAT(ReadError(dir.path()), HasSubstr(dir.path().string() + ": map file does not exist or is not a file"));
}

}  // namespace
}  // namespace hoidslam::io
