# Renders two inputs with the same pbdrr options and fails unless the two images are identical, byte for byte:
#
#   cmake -DEXE=/path/to/pbdrr -DFIRST=input1 -DSECOND=input2 -DOUTPUT_DIRECTORY=dir -DNAME=name
#         -P CompareRenders.cmake -- pbdrr options...
#
# Used with --exact: two files that hold the same volume in different layouts must give the same radiograph. With a
# word --vs among the options, the options before it render FIRST and those after it SECOND: two spellings of the
# same options must give the same image. With -DALSO="file1|file2", two more files the renders write (the first's and
# the second's, such as their channel images) must be identical too.
cmake_minimum_required(VERSION 3.16)
include(${CMAKE_CURRENT_LIST_DIR}/ArgumentsAfterSeparator.cmake)
pbdrr_arguments_after_separator(options)
file(MAKE_DIRECTORY "${OUTPUT_DIRECTORY}")
list(FIND options "--vs" split)
set(options_0 ${options})
set(options_1 ${options})
if(split GREATER -1)
  list(SUBLIST options 0 ${split} options_0)
  math(EXPR after "${split} + 1")
  list(SUBLIST options ${after} -1 options_1)
endif()
set(outputs "")
foreach(input IN ITEMS "${FIRST}" "${SECOND}")
  list(LENGTH outputs index)
  set(options ${options_${index}})
  set(output "${OUTPUT_DIRECTORY}/${NAME}_${index}.mha")
  file(REMOVE "${output}")
  execute_process(COMMAND "${EXE}" "${input}" -o "${output}" ${options} RESULT_VARIABLE exit_code ERROR_VARIABLE err
                  TIMEOUT 120)
  if(NOT exit_code STREQUAL "0")
    message(FATAL_ERROR "pbdrr ${input} ${options} failed (${exit_code}): ${err}")
  endif()
  list(APPEND outputs "${output}")
endforeach()
list(GET outputs 0 first_output)
list(GET outputs 1 second_output)
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files "${first_output}" "${second_output}" RESULT_VARIABLE differ)
if(differ)
  message(FATAL_ERROR "${FIRST} and ${SECOND} give different images (${first_output}, ${second_output})")
endif()
if(ALSO)
  string(REPLACE "|" ";" also "${ALSO}")
  list(GET also 0 first_also)
  list(GET also 1 second_also)
  execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files "${first_also}" "${second_also}" RESULT_VARIABLE differ)
  if(differ)
    message(FATAL_ERROR "the renders wrote different files ${first_also} and ${second_also}")
  endif()
endif()
message(STATUS "${FIRST} and ${SECOND} give the same image")
