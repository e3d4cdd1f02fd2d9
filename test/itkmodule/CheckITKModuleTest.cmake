# PointBasedDRR.ITKModuleTestConfigure: configures test/itkmodule (the module's test/ as an ITK tree adds it) in
# BINARY_DIR and checks that the test module registers the GoogleTest driver's tests and no other test.
#   cmake -DSOURCE_DIR=<test/itkmodule> -DBINARY_DIR=<dir> -DITK_DIR=<dir> -DGENERATOR=<generator>
#         -DC_COMPILER=<cc> -DCXX_COMPILER=<c++> -P CheckITKModuleTest.cmake
file(REMOVE_RECURSE "${BINARY_DIR}")
execute_process(
  COMMAND "${CMAKE_COMMAND}" -S "${SOURCE_DIR}" -B "${BINARY_DIR}" -G "${GENERATOR}" "-DITK_DIR=${ITK_DIR}"
          "-DCMAKE_C_COMPILER=${C_COMPILER}" "-DCMAKE_CXX_COMPILER=${CXX_COMPILER}"
  RESULT_VARIABLE _result OUTPUT_VARIABLE _output ERROR_VARIABLE _error)
if(NOT _result EQUAL 0)
  message(FATAL_ERROR "configuring test/itkmodule failed (${_result}):\n${_output}\n${_error}")
endif()
# itk_module() warns, as ITK's does, about every argument it does not know, e.g. the pieces of a DESCRIPTION cut at
# its semicolons.
if(_error MATCHES "Unknown argument")
  message(FATAL_ERROR "itk_module() does not understand itk-module.cmake:\n${_error}")
endif()
string(REGEX MATCH "-- PointBasedDRR-Test: [^\n]*" _summary "${_output}")
message(STATUS "${_summary}")

set(_testfile "${BINARY_DIR}/PointBasedDRR-Test/CTestTestfile.cmake")
if(NOT EXISTS "${_testfile}")
  message(FATAL_ERROR "no ${_testfile}: the test module registered no test")
endif()
file(READ "${_testfile}" _tests)
if(NOT _tests MATCHES "PointBasedDRRGTestDriver\\[1\\]_include\\.cmake")
  message(FATAL_ERROR "the GoogleTest driver's tests are not discovered (gtest_discover_tests):\n${_tests}")
endif()
if(_tests MATCHES "add_test\\(|subdirs\\(")
  message(FATAL_ERROR "the in-ITK branch of test/CMakeLists.txt registers tests of the stand-alone build:\n${_tests}")
endif()
message(STATUS "PointBasedDRR-Test registers the tests of PointBasedDRRGTestDriver and no other")
