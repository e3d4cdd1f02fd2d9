# Runs pbdrr once and checks how it ended. Used by the pbdrr.* tests (test/cli/CMakeLists.txt):
#
#   cmake -DEXE=/path/to/pbdrr -DEXPECT_EXIT=0|1|2|error [options] -P RunPbdrr.cmake [-- ARG...]
#
# pbdrr's arguments: the ;-list ARGS and/or everything after "--" (add_test passes lists best that way).
#   EXPECT_EXIT          0, 1 (run-time error), 2 (usage error), or "error": 1 or 2. A failure must be exactly 1 or 2
#                        (a signal, abort or any other code is a crash) and print "pbdrr: error: ..." on stderr.
#   EXPECT_STDERR_REGEX  stderr must match (the message naming the problem).
#   EXPECT_STDOUT_REGEX  stdout must match.
#   EXPECT_STDERR_EMPTY  ON: stderr must be empty (--quiet).
#   EXPECT_FILES         |-separated files that must exist, non-empty, after the run (deleted before it).
#   EXPECT_NO_FILES      |-separated files that must not exist after the run (deleted before it).
#   EXPECT_SIZE          "COLS ROWS": size of the first EXPECT_FILES entry (.mha/.mhd, .nrrd or .png).
#   OUTPUT_DIRECTORY     created before the run (where the tests write; pbdrr does not create directories).
#   REQUIRE              a path the test needs (real data under ../shared/data): absent, the test prints
#                        "SKIPPED: ..." and stops (the test's SKIP_REGULAR_EXPRESSION).
cmake_minimum_required(VERSION 3.16)

if(NOT EXE)
  message(FATAL_ERROR "RunPbdrr: EXE (the pbdrr executable) is not set")
endif()
if(NOT DEFINED EXPECT_EXIT)
  message(FATAL_ERROR "RunPbdrr: EXPECT_EXIT is not set")
endif()

if(DEFINED REQUIRE AND NOT EXISTS "${REQUIRE}")
  message(STATUS "SKIPPED: ${REQUIRE} is absent (real data from ../shared/data)")
  return()
endif()

include(${CMAKE_CURRENT_LIST_DIR}/ArgumentsAfterSeparator.cmake)
pbdrr_arguments_after_separator(after)
set(arguments ${ARGS} ${after})

if(OUTPUT_DIRECTORY)
  file(MAKE_DIRECTORY "${OUTPUT_DIRECTORY}")
endif()
string(REPLACE "|" ";" expect_files "${EXPECT_FILES}")
string(REPLACE "|" ";" expect_no_files "${EXPECT_NO_FILES}")
foreach(file IN LISTS expect_files expect_no_files)
  file(REMOVE "${file}")
  get_filename_component(directory "${file}" DIRECTORY)
  file(MAKE_DIRECTORY "${directory}")
endforeach()

string(REPLACE ";" " " shown "${arguments}")
message(STATUS "running: ${EXE} ${shown}")
execute_process(
  COMMAND "${EXE}" ${arguments}
  RESULT_VARIABLE exit_code
  OUTPUT_VARIABLE out
  ERROR_VARIABLE err
  TIMEOUT 120)
message(STATUS "exit code: ${exit_code}\n--- stdout ---\n${out}--- stderr ---\n${err}--------------")

set(failures "")
if(EXPECT_EXIT STREQUAL "error")
  if(NOT (exit_code STREQUAL "1" OR exit_code STREQUAL "2"))
    string(APPEND failures "\n  exit code '${exit_code}', expected an error exit: 1 or 2 (anything else is a crash)")
  endif()
elseif(NOT exit_code STREQUAL EXPECT_EXIT)
  string(APPEND failures "\n  exit code '${exit_code}', expected ${EXPECT_EXIT}")
endif()
if(NOT EXPECT_EXIT STREQUAL "0")
  if(NOT err MATCHES "pbdrr: error: ")
    string(APPEND failures "\n  no 'pbdrr: error: ...' message on stderr")
  endif()
  if(err MATCHES "itk::ExceptionObject|Location: |terminate called|Segmentation fault|Aborted")
    string(APPEND failures "\n  stderr shows a raw exception dump or a crash instead of a message")
  endif()
endif()
if(DEFINED EXPECT_STDERR_REGEX AND NOT err MATCHES "${EXPECT_STDERR_REGEX}")
  string(APPEND failures "\n  stderr does not match '${EXPECT_STDERR_REGEX}'")
endif()
if(DEFINED EXPECT_STDOUT_REGEX AND NOT out MATCHES "${EXPECT_STDOUT_REGEX}")
  string(APPEND failures "\n  stdout does not match '${EXPECT_STDOUT_REGEX}'")
endif()
if(EXPECT_STDERR_EMPTY AND NOT err STREQUAL "")
  string(APPEND failures "\n  stderr is not empty")
endif()
foreach(file IN LISTS expect_files)
  if(NOT EXISTS "${file}" OR IS_DIRECTORY "${file}")
    string(APPEND failures "\n  output ${file} was not written")
  else()
    file(SIZE "${file}" size)
    if(size EQUAL 0)
      string(APPEND failures "\n  output ${file} is empty")
    endif()
  endif()
endforeach()
foreach(file IN LISTS expect_no_files)
  if(EXISTS "${file}")
    file(SIZE "${file}" size)
    string(APPEND failures "\n  ${file} exists after the run (${size} bytes); it should not")
  endif()
endforeach()

if(DEFINED EXPECT_SIZE AND NOT failures)
  list(GET expect_files 0 file)
  string(TOLOWER "${file}" lower)
  set(size "")
  if(lower MATCHES "\\.(mha|mhd)$")
    file(STRINGS "${file}" lines LIMIT_INPUT 4096 REGEX "^DimSize = ")
    if(lines MATCHES "^DimSize = ([0-9 ]+)")
      string(STRIP "${CMAKE_MATCH_1}" size)
    endif()
  elseif(lower MATCHES "\\.nrrd$")
    file(STRINGS "${file}" lines LIMIT_INPUT 4096 REGEX "^sizes: ")
    if(lines MATCHES "^sizes: ([0-9 ]+)")
      string(STRIP "${CMAKE_MATCH_1}" size)
    endif()
  elseif(lower MATCHES "\\.png$")
    # IHDR: width and height, big-endian 32-bit, at bytes 16..23.
    file(READ "${file}" header OFFSET 16 LIMIT 8 HEX)
    string(SUBSTRING "${header}" 0 8 width)
    string(SUBSTRING "${header}" 8 8 height)
    math(EXPR width "0x${width}")
    math(EXPR height "0x${height}")
    set(size "${width} ${height}")
  else()
    message(FATAL_ERROR "RunPbdrr: EXPECT_SIZE cannot read the size of ${file}")
  endif()
  if(NOT size STREQUAL EXPECT_SIZE)
    string(APPEND failures "\n  ${file} has size '${size}', expected '${EXPECT_SIZE}'")
  endif()
endif()

if(failures)
  message(FATAL_ERROR "pbdrr ${shown}:${failures}")
endif()
message(STATUS "OK")
