# Runs an example as a test: cmake [options] -P RunExample.cmake -- COMMAND [ARGUMENTS...]
#   -DINPUT=FILE          the example reads FILE (already among the arguments): absent, the test prints SKIPPED (the
#                         tests' SKIP_REGULAR_EXPRESSION) instead of failing, as for the shared real CT
#   -DPYTHON_ITK=PYTHON   the example is a Python script: if PYTHON cannot import itk.PointBasedDRRImageFilter, SKIPPED
#   -DOUTPUTS=A|B|...     files the example must write (|-separated; removed first, so that old ones do not count)
#   -DCHECK_BOUNDS=ON     CompareWithRayCast: each method's NRMSE must not exceed the expected NRMSE it prints
# The command must exit with 0; its output is echoed.
cmake_minimum_required(VERSION 3.16.3)
include(${CMAKE_CURRENT_LIST_DIR}/../test/cli/ArgumentsAfterSeparator.cmake)
pbdrr_arguments_after_separator(command)

if(DEFINED INPUT AND NOT EXISTS "${INPUT}")
  message("SKIPPED: ${INPUT} is absent (shared real CT data is not on this machine)")
  return()
endif()
if(DEFINED PYTHON_ITK)
  execute_process(COMMAND "${PYTHON_ITK}" -c "import itk; itk.PointBasedDRRImageFilter" RESULT_VARIABLE importable
                  OUTPUT_QUIET ERROR_QUIET)
  if(NOT importable EQUAL 0)
    message("SKIPPED: ${PYTHON_ITK} cannot import itk.PointBasedDRRImageFilter (ITK Python wrapping with "
            "PointBasedDRR is not available)")
    return()
  endif()
endif()

string(REPLACE "|" ";" outputs "${OUTPUTS}")
foreach(output IN LISTS outputs)
  file(REMOVE "${output}")
endforeach()

execute_process(COMMAND ${command} RESULT_VARIABLE result OUTPUT_VARIABLE printed ERROR_VARIABLE printed_errors)
message("${printed}${printed_errors}")
if(NOT result EQUAL 0)
  message(FATAL_ERROR "the example failed (${result}): ${command}")
endif()
foreach(output IN LISTS outputs)
  if(NOT EXISTS "${output}")
    message(FATAL_ERROR "the example wrote no ${output}")
  endif()
endforeach()

if(CHECK_BOUNDS)
  # Table rows: | method | wall time (s) | RMSE | NRMSE (%) | <= expected NRMSE (%) | max abs error | sum ratio |
  string(REGEX MATCHALL "\n\\| (point-based|ITK ray caster)[^\n]*" rows "${printed}")
  list(LENGTH rows number_of_rows)
  if(NOT number_of_rows EQUAL 2)
    message(FATAL_ERROR "expected the point-based and ray-caster rows in the table, found ${number_of_rows}")
  endif()
  foreach(row IN LISTS rows)
    string(REPLACE "|" ";" cells "${row}")
    list(GET cells 1 method)
    list(GET cells 4 nrmse)
    list(GET cells 5 expected)
    string(STRIP "${method}" method)
    string(STRIP "${nrmse}" nrmse)
    string(REGEX REPLACE "^ *<= *([^ ]+) *$" "\\1" expected "${expected}")
    if(NOT nrmse MATCHES "^[0-9.e+-]+$" OR NOT expected MATCHES "^[0-9.e+-]+$")
      message(FATAL_ERROR "cannot read the NRMSE (${nrmse}) or the expected NRMSE (${expected}) of ${method}")
    endif()
    if(nrmse GREATER expected)
      message(FATAL_ERROR "${method}: NRMSE ${nrmse}% exceeds its expected ${expected}%")
    endif()
    message("${method}: NRMSE ${nrmse}% <= expected ${expected}%")
  endforeach()
endif()
