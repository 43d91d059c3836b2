#pragma once
// The plantnbv tool as a test runs it: a temporary directory per test, the tool's exit
// code, stdout and stderr, and the check of a one-line error.

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/io/cloud_io.h>

namespace plantnbv {
namespace test {

namespace fs = std::filesystem;

inline const std::string kTool = std::string(PLANTNBV_BINARY_DIR) + "/bin/plantnbv";
inline const std::string kFixtures = std::string(PLANTNBV_DATA_DIR) + "/fixtures";

struct ToolRun {
  int code = -1;
  std::string out, err;
};

inline std::string slurp(const fs::path& p)
{
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The standard output of a shell command (empty if it fails or prints nothing).
inline std::string commandOutput(const std::string& command)
{
  std::string out;
  if (FILE* pipe = ::popen(command.c_str(), "r")) {
    char buffer[256];
    for (std::size_t n; (n = std::fread(buffer, 1, sizeof(buffer), pipe)) > 0;)
      out.append(buffer, n);
    ::pclose(pipe);
  }
  return out;
}

class CliTest : public ::testing::Test {
protected:
  void SetUp() override
  {
    // The process id keeps two builds' test runs on one machine apart.
    dir_ = fs::temp_directory_path() /
           ("plantnbv_cli_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) +
            "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  ToolRun run(const std::string& args) const
  {
    const std::string cmd = kTool + " " + args + " >" + path("stdout") + " 2>" +
                            path("stderr") + " </dev/null";
    const int status = std::system(cmd.c_str());
    ToolRun r;
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    r.out = slurp(path("stdout"));
    r.err = slurp(path("stderr"));
    return r;
  }

  void write(const std::string& name, const std::string& text) const
  {
    std::ofstream(path(name)) << text;
  }

  /// A 4 x 4 x 1 lattice of points 1/64 m apart from (1, 1, 513) / 512 m, shifted by `dx`
  /// along x. Powers of two keep every coordinate and distance exact in float.
  void writeLattice(const std::string& name, float dx) const
  {
    pcl::PointCloud<pcl::PointXYZ> cloud;
    const float origin = 1.0f / 512, spacing = 1.0f / 64;
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j)
        cloud.push_back(pcl::PointXYZ(origin + spacing * i + dx, origin + spacing * j,
                                      1.0f + origin));
    plantnbv::io::saveCloud(path(name), cloud);
  }

  fs::path dir_;
};

/// Errors are one line on stderr that starts with "plantnbv".
inline void expectOneLineError(const ToolRun& r, int code, const std::string& needle)
{
  EXPECT_EQ(r.code, code) << r.err;
  EXPECT_EQ(r.err.rfind("plantnbv", 0), 0u) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find(needle), std::string::npos)
      << "'" << needle << "' not in: " << r.err;
}

} // namespace test
} // namespace plantnbv
