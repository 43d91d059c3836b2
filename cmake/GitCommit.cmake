# Writes OUTPUT, a header defining PLANTNBV_GIT_COMMIT: the commit of SOURCE_DIR's
# checkout ("0123456789ab", "+dirty" after it when tracked files differ from it), or
# "unknown" outside a git checkout. Run at every build (cmake -P); the file is rewritten
# only when the text changes, so only its includers recompile after a new commit.
execute_process(COMMAND git -C "${SOURCE_DIR}" rev-parse --short=12 HEAD
                OUTPUT_VARIABLE commit OUTPUT_STRIP_TRAILING_WHITESPACE
                RESULT_VARIABLE failed ERROR_QUIET)
if(failed OR commit STREQUAL "")
  set(commit "unknown")
else()
  execute_process(COMMAND git -C "${SOURCE_DIR}" diff --quiet HEAD --
                  RESULT_VARIABLE dirty ERROR_QUIET)
  if(dirty)
    string(APPEND commit "+dirty")
  endif()
endif()
set(text "#pragma once\n#define PLANTNBV_GIT_COMMIT \"${commit}\"\n")
if(EXISTS "${OUTPUT}")
  file(READ "${OUTPUT}" old)
endif()
if(NOT old STREQUAL text)
  file(WRITE "${OUTPUT}" "${text}")
endif()
