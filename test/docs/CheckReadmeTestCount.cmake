# The README's count of tests ("(N tests, ...") is the suite's: ctest -N in this build (issue 40, item 6: a number
# that goes stale in the README is made true, here by a test that fails when it is not).
#   cmake -DCTEST=ctest -DBUILD_DIR=<build> -DREADME=<README.md> -P CheckReadmeTestCount.cmake
cmake_minimum_required(VERSION 3.16)
execute_process(COMMAND "${CTEST}" -N WORKING_DIRECTORY "${BUILD_DIR}" OUTPUT_VARIABLE listing RESULT_VARIABLE code)
if(NOT code EQUAL 0 OR NOT listing MATCHES "Total Tests: ([0-9]+)")
  message(FATAL_ERROR "ctest -N in ${BUILD_DIR} failed (${code}):\n${listing}")
endif()
set(suite ${CMAKE_MATCH_1})
file(READ "${README}" readme)
if(NOT readme MATCHES "\\(([0-9]+) tests,")
  message(FATAL_ERROR "${README} states no count of tests (\"(N tests,\")")
endif()
if(NOT CMAKE_MATCH_1 EQUAL suite)
  message(FATAL_ERROR "${README} says ${CMAKE_MATCH_1} tests; the suite has ${suite}: update the README")
endif()
message(STATUS "the README's ${suite} tests are the suite's")
