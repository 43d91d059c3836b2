// The tool's version and the commit it was built from (git_commit.h, written at build
// time by cmake/GitCommit.cmake): only this file recompiles after a new commit.

#include "git_commit.h"

#include "commands.h"

namespace plantnbv {
namespace app {

const char* toolVersion()
{
  return PLANTNBV_VERSION;
}

const char* toolCommit()
{
  return PLANTNBV_GIT_COMMIT;
}

} // namespace app
} // namespace plantnbv
