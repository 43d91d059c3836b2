# ctest's readme_test_command_in_ci: the README's test command (its line that starts
# with scripts/install-deps and runs ctest) is a line of .ci/run, verbatim, so that CI
# runs what the README tells users to run.
# Usage: cmake -DSOURCE_DIR=<repository root> -P readme_test_command_in_ci.cmake
file(STRINGS ${SOURCE_DIR}/README.md readme_lines REGEX "^scripts/install-deps .*ctest ")
list(LENGTH readme_lines count)
if(NOT count EQUAL 1)
  message(FATAL_ERROR "README.md: expected one test command (a line starting with "
                      "scripts/install-deps that runs ctest), found ${count}")
endif()
file(STRINGS ${SOURCE_DIR}/.ci/run ci_lines)
list(FIND ci_lines "${readme_lines}" at)
if(at EQUAL -1)
  message(FATAL_ERROR "the README's test command is not a line of .ci/run (keep the two "
                      "in sync):\n  ${readme_lines}")
endif()
message(STATUS "readme_test_command_in_ci: .ci/run runs the README's test command")
