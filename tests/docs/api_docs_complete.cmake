# ctest's api_docs_complete: runs Doxygen over the public headers with the API
# reference's configuration (<build>/doc/Doxyfile, from docs/Doxyfile.in) and fails,
# listing them, on any warning: an undocumented public member, a \param naming no
# parameter, a broken \ref. Writes XML only (nothing to read, quicker than HTML) into
# WORK_DIR, so that it never touches the HTML of the doc target.
# Usage: cmake -DDOXYGEN=... -DDOXYFILE=... -DWORK_DIR=... -P api_docs_complete.cmake
foreach(var DOXYGEN DOXYFILE WORK_DIR)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "api_docs_complete: -D${var}=... is missing")
  endif()
endforeach()

file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})
set(log ${WORK_DIR}/warnings.log)
file(WRITE ${WORK_DIR}/Doxyfile
  "@INCLUDE = ${DOXYFILE}\n"
  "OUTPUT_DIRECTORY = ${WORK_DIR}\n"
  "WARN_LOGFILE = ${log}\n"
  "GENERATE_HTML = NO\n"
  "GENERATE_XML = YES\n")
execute_process(COMMAND ${DOXYGEN} ${WORK_DIR}/Doxyfile
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "api_docs_complete: doxygen failed (exit ${rc}):\n${out}")
endif()
file(STRINGS ${log} warnings REGEX "warning:")
list(LENGTH warnings count)
file(READ ${log} text)
if(count GREATER 0 OR NOT text STREQUAL "")
  message(FATAL_ERROR "api_docs_complete: ${count} Doxygen warnings in the public headers "
                      "(document each member named; docs/Doxyfile.in):\n${text}")
endif()
message(STATUS "api_docs_complete: no Doxygen warnings")
