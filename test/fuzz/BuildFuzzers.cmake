# fuzz.Build: configures and builds the fuzz targets with clang in BINARY_DIR (cmake -P, from test/fuzz/CMakeLists.txt).
# Prints FUZZ-SKIPPED (the test is then skipped) when clang or libFuzzer's runtime is missing.

find_program(FUZZ_CLANGXX NAMES clang++ clang++-14 clang++-15 clang++-16)
find_program(FUZZ_CLANG NAMES clang clang-14 clang-15 clang-16)
if(NOT FUZZ_CLANGXX OR NOT FUZZ_CLANG)
  message("FUZZ-SKIPPED: clang is not installed (Debian: apt-get install clang libclang-rt-14-dev)")
  return()
endif()

# libFuzzer's runtime and the sanitizers' (Debian's libclang-rt-14-dev): link a trivial fuzz target.
set(probe_dir ${BINARY_DIR}/probe)
file(MAKE_DIRECTORY ${probe_dir})
file(WRITE ${probe_dir}/probe.cxx
     "#include <cstddef>\n#include <cstdint>\n"
     "extern \"C\" int LLVMFuzzerTestOneInput(const uint8_t *, size_t) { return 0; }\n")
execute_process(COMMAND ${FUZZ_CLANGXX} -fsanitize=fuzzer,address,undefined ${probe_dir}/probe.cxx
                        -o ${probe_dir}/probe
                RESULT_VARIABLE probe_result OUTPUT_VARIABLE probe_output ERROR_VARIABLE probe_output)
if(NOT probe_result EQUAL 0)
  message("${probe_output}")
  message("FUZZ-SKIPPED: ${FUZZ_CLANGXX} cannot link a libFuzzer target with AddressSanitizer and "
          "UndefinedBehaviorSanitizer (Debian: apt-get install libclang-rt-14-dev)")
  return()
endif()

execute_process(COMMAND ${CMAKE_COMMAND} -S ${SOURCE_DIR} -B ${BINARY_DIR} -DCMAKE_C_COMPILER=${FUZZ_CLANG}
                        -DCMAKE_CXX_COMPILER=${FUZZ_CLANGXX} -DCMAKE_BUILD_TYPE=RelWithDebInfo
                        -DPOINTBASEDDRR_BUILD_FUZZERS=ON
                RESULT_VARIABLE result)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "configuring the fuzz build in ${BINARY_DIR} failed")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build ${BINARY_DIR} -j 2 RESULT_VARIABLE result)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "building the fuzz targets in ${BINARY_DIR} failed")
endif()
