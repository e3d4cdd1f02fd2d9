# fuzz.<target>: runs one fuzz target for RUNS executions with a fixed seed, at most MAX_TOTAL_TIME seconds
# (cmake -P, from test/fuzz/CMakeLists.txt). The committed seeds (SEEDS) are read only; what the run adds to the
# corpus goes to WORK_DIR/corpus, emptied first, and a crashing input to WORK_DIR/crash-*. Any finding fails the test.

if(NOT EXISTS ${FUZZER})
  message("FUZZ-SKIPPED: ${FUZZER} was not built (see the output of fuzz.Build: clang or libFuzzer missing)")
  return()
endif()

file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR}/corpus)
set(options -runs=${RUNS} -seed=1 -max_total_time=${MAX_TOTAL_TIME} -timeout=20 -rss_limit_mb=2048
            -print_final_stats=1 -artifact_prefix=${WORK_DIR}/)
if(EXISTS ${DICTIONARY})
  list(APPEND options -dict=${DICTIONARY})
endif()
find_program(FUZZ_SYMBOLIZER NAMES llvm-symbolizer llvm-symbolizer-14 PATHS /usr/lib/llvm-14/bin)
if(FUZZ_SYMBOLIZER)
  set(ENV{ASAN_SYMBOLIZER_PATH} ${FUZZ_SYMBOLIZER})
endif()
set(ENV{UBSAN_OPTIONS} "print_stacktrace=1:halt_on_error=1")
# ITK's XML reader leaks expat's parser on a malformed file: see lsan.supp.
set(ENV{LSAN_OPTIONS} "suppressions=${CMAKE_CURRENT_LIST_DIR}/lsan.supp:print_suppressions=0")

string(REPLACE ";" " " command_line "${FUZZER} ${options} ${WORK_DIR}/corpus ${SEEDS}")
message("${command_line}")
execute_process(COMMAND ${FUZZER} ${options} ${WORK_DIR}/corpus ${SEEDS} RESULT_VARIABLE result)
if(NOT result EQUAL 0)
  file(GLOB artifacts ${WORK_DIR}/crash-* ${WORK_DIR}/leak-* ${WORK_DIR}/timeout-* ${WORK_DIR}/oom-*)
  message(FATAL_ERROR "${FUZZER} found a problem (exit code ${result}); the input: ${artifacts}\n"
                      "Reproduce: ${FUZZER} <input>; minimize: ${FUZZER} -minimize_crash=1 -runs=10000 <input>")
endif()
