# Sanitizer and fuzzing builds (docs/reliability.md).
#   PLANTNBV_SANITIZE=ON    AddressSanitizer + UndefinedBehaviorSanitizer on everything
#                           built here: libraries, apps, tests (GCC or clang).
#   PLANTNBV_BUILD_FUZZ=ON  the libFuzzer targets of tests/fuzz (clang only); implies
#                           the sanitizers and adds coverage instrumentation to the
#                           libraries (-fsanitize=fuzzer-no-link).
# Included before any target is defined, so the flags reach every target.

option(PLANTNBV_SANITIZE "Build with AddressSanitizer and UndefinedBehaviorSanitizer" OFF)
option(PLANTNBV_BUILD_FUZZ "Build the libFuzzer targets in tests/fuzz (clang; implies PLANTNBV_SANITIZE)" OFF)

if(PLANTNBV_BUILD_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "PLANTNBV_BUILD_FUZZ needs clang (libFuzzer), not "
                        "${CMAKE_CXX_COMPILER_ID}: configure with -DCMAKE_C_COMPILER=clang-14 "
                        "-DCMAKE_CXX_COMPILER=clang++-14 (scripts/fuzz does)")
  endif()
  set(PLANTNBV_SANITIZE ON)
endif()

if(PLANTNBV_SANITIZE)
  # Any report is fatal (no recovery), so a test or fuzz run fails on the first one.
  set(PLANTNBV_SANITIZER_FLAGS -fsanitize=address,undefined -fno-sanitize-recover=all
                               -fno-omit-frame-pointer)
  add_compile_options(${PLANTNBV_SANITIZER_FLAGS})
  add_link_options(-fsanitize=address,undefined)
  if(PLANTNBV_BUILD_FUZZ)
    add_compile_options(-fsanitize=fuzzer-no-link)
  endif()
  # Runtime options, with the suppressions of reports in third-party libraries
  # (tests/sanitizer/*.supp). ctest sets them, unless already set, before it lists or
  # runs any test (the list of a gtest program is made by running it); scripts/fuzz
  # sets them for the fuzz targets.
  set(supp ${PROJECT_SOURCE_DIR}/tests/sanitizer)
  # Reports name functions and lines only with a symbolizer (package llvm-14).
  find_program(PLANTNBV_LLVM_SYMBOLIZER NAMES llvm-symbolizer-14 llvm-symbolizer)
  set(symbolizer "")
  if(PLANTNBV_LLVM_SYMBOLIZER)
    set(symbolizer ":external_symbolizer_path=${PLANTNBV_LLVM_SYMBOLIZER}")
  endif()
  # Not strict_string_checks: Assimp 5.2.5's OBJ parser gives strtol line buffers that
  # end in '\n' without a NUL; strtol stops at the '\n' and reads nothing past the
  # buffer, but the strict check reports every such call (docs/reliability.md).
  set(PLANTNBV_ASAN_OPTIONS "detect_leaks=1:detect_stack_use_after_return=1:check_initialization_order=1:strict_init_order=1${symbolizer}")
  # Not intercept_tls_get_addr: when a dynamic thread-local block starts 16 bytes past a
  # page, LeakSanitizer 14 takes it for glibc 2.19's, reads ASan's chunk header before it
  # as {size, start} and scans from a small address: its tracer dies at exit ("Tracer
  # caught signal 11"), as after rendering for some lengths of the PNG's path. Glibc 2.36
  # allocates these blocks with malloc and keeps them in the thread's dtv, so the check
  # reaches them without the interception (docs/reliability.md).
  set(PLANTNBV_LSAN_OPTIONS "suppressions=${supp}/lsan.supp:print_suppressions=0:intercept_tls_get_addr=0")
  set(PLANTNBV_UBSAN_OPTIONS "print_stacktrace=1:halt_on_error=1:suppressions=${supp}/ubsan.supp${symbolizer}")
  set(script "# Written by cmake/Sanitizers.cmake: the sanitizer options of every test.\n")
  foreach(var ASAN LSAN UBSAN)
    string(APPEND script "if(NOT DEFINED ENV{${var}_OPTIONS})\n"
                         "  set(ENV{${var}_OPTIONS} \"${PLANTNBV_${var}_OPTIONS}\")\n"
                         "endif()\n")
  endforeach()
  file(WRITE ${PROJECT_BINARY_DIR}/sanitizer_env.cmake "${script}")
  set_property(DIRECTORY ${PROJECT_SOURCE_DIR} APPEND PROPERTY TEST_INCLUDE_FILES
               ${PROJECT_BINARY_DIR}/sanitizer_env.cmake)
  list(JOIN PLANTNBV_SANITIZER_FLAGS " " flags)
  message(STATUS "plantnbv: sanitizers on (${flags})")
endif()
