// Files as an attacker or a hostile input shapes them: links planted where a writer's temporary
// would go, PNG headers that declare more pixels than the memory budget holds.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include "ifsforge/core/error.h"
#include "ifsforge/core/image.h"
#include "ifsforge/io/atomic_file.h"
#include "ifsforge/io/png.h"

namespace ifsforge {
namespace {

std::string scratch(const std::string& name) {
  const std::string folder = ::testing::TempDir() + "ifsforge_hostile_" + name;
  std::string command = "rm -rf '" + folder + "' && mkdir -p '" + folder + "'";
  EXPECT_EQ(std::system(command.c_str()), 0);
  return folder;
}

std::string read(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(AtomicFile, TemporariesHaveUnguessableNamesBesideTheTarget) {
  const std::string folder = scratch("names");
  AtomicFile a(folder + "/out.png"), b(folder + "/out.png");
  const std::regex pattern(".*/out\\.png\\.tmp-[0-9a-f]{16}");
  EXPECT_TRUE(std::regex_match(a.temporary_path(), pattern)) << a.temporary_path();
  EXPECT_NE(a.temporary_path(), b.temporary_path());
}

TEST(AtomicFile, LinksPlantedAtPredictableNamesAreNeverFollowed) {
  // The names a writer once used (target.tmp-<pid>-<n>) all point at a file the attacker wants
  // overwritten; the write must land in the target, a regular file, and the victim stay intact.
  const std::string folder = scratch("links");
  const std::string victim = folder + "/victim.txt", target = folder + "/out.bin";
  std::ofstream(victim) << "keep me";
  for (int n = 0; n < 64; ++n) {
    const std::string link = target + ".tmp-" + std::to_string(getpid()) + "-" + std::to_string(n);
    ASSERT_EQ(symlink(victim.c_str(), link.c_str()), 0);
  }
  AtomicFile file(target);
  write_bytes(file.file(), "payload", 7, target);
  file.commit();
  EXPECT_EQ(read(victim), "keep me");
  EXPECT_EQ(read(target), "payload");
  struct stat info;
  ASSERT_EQ(lstat(target.c_str(), &info), 0);
  EXPECT_TRUE(S_ISREG(info.st_mode));
}

// A PNG of its signature, IHDR, an empty IDAT and IEND: a few dozen bytes that declare width x height.
std::string png_header_only(std::uint32_t width, std::uint32_t height) {
  auto be32 = [](std::uint32_t v) {
    return std::string{char(v >> 24), char(v >> 16), char(v >> 8), char(v)};
  };
  auto crc = [](const std::string& bytes) {
    std::uint32_t c = 0xffffffffu;
    for (unsigned char b : bytes) {
      c ^= b;
      for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
    }
    return c ^ 0xffffffffu;
  };
  auto chunk = [&](const std::string& type, const std::string& data) {
    return be32(std::uint32_t(data.size())) + type + data + be32(crc(type + data));
  };
  const std::string ihdr = be32(width) + be32(height) + std::string{8, 0, 0, 0, 0};  // 8-bit gray
  const std::string empty_stream("\x78\x9c\x03\x00\x00\x00\x00\x01", 8);  // zlib of no bytes
  return std::string("\x89PNG\r\n\x1a\n", 8) + chunk("IHDR", ihdr) + chunk("IDAT", empty_stream) + chunk("IEND", "");
}

TEST(PngReader, AHeaderDeclaringMorePixelsThanTheBudgetIsRefusedBeforeDecoding) {
  const std::string folder = scratch("png");
  const std::string path = folder + "/huge.png";
  std::ofstream(path, std::ios::binary) << png_header_only(1000000, 1000000);
  try {
    read_png(path);
    FAIL() << "a 10^12-pixel PNG was accepted";
  } catch (const MemoryBudgetError& e) {
    EXPECT_NE(std::string(e.what()).find("1000000x1000000"), std::string::npos) << e.what();
  }
}

TEST(Image, EveryImageIsCheckedAgainstTheBudgetWhereItIsAllocated) {
  EXPECT_THROW(Image(65535, 65535, 4096), MemoryBudgetError);
  EXPECT_THROW(Image(-1, 4, 1), InputError);
  EXPECT_EQ(Image(3, 2, 4).pixels.size(), 24u);
}

}  // namespace
}  // namespace ifsforge
