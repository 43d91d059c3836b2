// Files written whole or not at all, and files read only when they are regular files.

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/stat.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <plantnbv/common/error.h>
#include <plantnbv/common/file_io.h>

#include "file_size_limit.h"

using namespace plantnbv;
using plantnbv::test::FileSizeLimit;
namespace fs = std::filesystem;

namespace {

class FileIo : public ::testing::Test {
protected:
  void SetUp() override
  {
    dir_ = fs::temp_directory_path() /
           ("plantnbv_file_io_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) +
            "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string slurp(const fs::path& p) const
  {
    std::ifstream in(p, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }
  /// The names in the directory (temporary files included).
  std::size_t entries() const
  {
    return std::size_t(
        std::distance(fs::directory_iterator(dir_), fs::directory_iterator()));
  }
  fs::path dir_;
};

} // namespace

TEST_F(FileIo, AWrittenFileReplacesThePreviousOneWhole)
{
  const fs::path path = dir_ / "a.txt";
  writeFileAtomically(path, "first");
  EXPECT_EQ(slurp(path), "first");
  writeFileAtomically(path, [](std::ostream& out) {
    for (int i = 0; i < 100000; ++i) // more than the stream's buffer
      out << i << '\n';
  });
  EXPECT_EQ(slurp(path).substr(0, 6), "0\n1\n2\n");
  EXPECT_EQ(slurp(path).size(), 588890u);
  EXPECT_EQ(entries(), 1u); // no temporary file left
}

TEST_F(FileIo, AFailedWriteLeavesThePreviousFileAndNamesTheFileAndTheReason)
{
  const fs::path path = dir_ / "cloud.pcd";
  const std::string good(100000, 'g');
  writeFileAtomically(path, good);
  // Limits below, at and beyond the stream's 64 KiB buffer: the failure comes from a
  // write in the middle, from the last one, or from the close.
  for (const rlim_t limit : {rlim_t(0), rlim_t(1000), rlim_t(65536), rlim_t(99999)}) {
    try {
      const FileSizeLimit full(limit);
      writeFileAtomically(path, std::string(100000, 'n'));
      ADD_FAILURE() << "a write past the limit " << limit << " succeeded";
    } catch (const IoError& e) {
      EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("File too large"), std::string::npos)
          << e.what();
    }
    EXPECT_EQ(slurp(path), good) << limit;
    EXPECT_EQ(entries(), 1u) << limit;
  }
  // A writer that throws half-way: the previous file stays too.
  EXPECT_THROW(writeFileAtomically(path,
                                   [](std::ostream& out) {
                                     out << "half";
                                     throw InvalidArgumentError("stop");
                                   }),
               InvalidArgumentError);
  EXPECT_EQ(slurp(path), good);
  EXPECT_EQ(entries(), 1u);
}

TEST_F(FileIo, WhereNothingCanBeWrittenTheErrorNamesThePath)
{
  EXPECT_THROW(writeFileAtomically(dir_ / "no" / "such" / "x.txt", "x"), IoError);
  fs::create_directories(dir_ / "d");
  try {
    writeFileAtomically(dir_ / "d", "x"); // a directory in the way
    FAIL();
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find((dir_ / "d").string()), std::string::npos);
  }
  EXPECT_TRUE(fs::is_directory(dir_ / "d"));
}

TEST_F(FileIo, OnlyRegularFilesAreRead)
{
  writeFileAtomically(dir_ / "f", "x");
  EXPECT_NO_THROW(requireRegularFile(dir_ / "f"));
  fs::create_symlink(dir_ / "f", dir_ / "link");
  EXPECT_NO_THROW(requireRegularFile(dir_ / "link"));
  EXPECT_THROW(requireRegularFile(dir_ / "missing"), FileNotFoundError);
  EXPECT_THROW(requireRegularFile(dir_ / "f" / "below"), FileNotFoundError);
  fs::create_directories(dir_ / "d.json");
  ASSERT_EQ(::mkfifo((dir_ / "p.json").c_str(), 0600), 0);
  for (const char* name : {"d.json", "p.json"}) {
    try {
      requireRegularFile(dir_ / name);
      ADD_FAILURE() << name;
    } catch (const IoError& e) {
      EXPECT_EQ(std::string(e.what()).rfind((dir_ / name).string() + ": ", 0), 0u)
          << e.what();
    }
  }
  EXPECT_TRUE(isAtomicFileTemporary(".x.json.tmp.12.0"));
  EXPECT_FALSE(isAtomicFileTemporary("x.json"));
}
