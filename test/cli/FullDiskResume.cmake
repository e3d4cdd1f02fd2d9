# A full disk, without root (issue 39): writes past a file size limit (prlimit --fsize, RLIMIT_FSIZE) fail with EFBIG,
# as on a full disk. A single view and a batch each fail with a message naming the file and leave no cut file under
# an output's name; a cut view left by an earlier version is not counted done; after the limit is lifted, --resume
# completes the batch, and every file equals a clean run's, bit for bit.
#
#   cmake -DEXE=/path/to/pbdrr -DINPUT=volume.mha -DWORK=folder -P FullDiskResume.cmake
cmake_minimum_required(VERSION 3.16)
foreach(variable EXE INPUT WORK)
  if(NOT ${variable})
    message(FATAL_ERROR "FullDiskResume: ${variable} is not set")
  endif()
endforeach()
find_program(PRLIMIT prlimit)
if(NOT PRLIMIT)
  message(FATAL_ERROR "FullDiskResume: prlimit (util-linux) is missing")
endif()
file(REMOVE_RECURSE "${WORK}")
foreach(folder clean single batch)
  file(MAKE_DIRECTORY "${WORK}/${folder}")
endforeach()
# 32 x 32 float views: 4096 bytes of pixels after a header of about 300; the limit cuts every image, not its view file.
set(common --size 32 32 --samples 2e4 --seed 9 --angles 8 --angle-step 45 -q)
set(limit 3000)

# run(EXPECT_EXIT STDERR_VARIABLE args...): pbdrr, under the limit if LIMITED is set.
function(run expected result)
  if(LIMITED)
    set(prefix "${PRLIMIT}" --fsize=${limit} --)
  endif()
  execute_process(COMMAND ${prefix} "${EXE}" "${INPUT}" ${ARGN} RESULT_VARIABLE code ERROR_VARIABLE err TIMEOUT 120)
  if(NOT code EQUAL expected)
    string(REPLACE ";" " " shown "${ARGN}")
    message(FATAL_ERROR "pbdrr ${shown}: exit ${code}, expected ${expected}\n${err}")
  endif()
  set(${result} "${err}" PARENT_SCOPE)
endfunction()

# no_cut_files(FOLDER): every image in FOLDER is whole (its size is the clean run's), and no temporary file is left.
function(no_cut_files folder what)
  file(GLOB images "${folder}/*.mha")
  foreach(image ${images})
    get_filename_component(name "${image}" NAME)
    file(SIZE "${image}" size)
    file(SIZE "${WORK}/clean/${name}" expected)
    if(NOT size EQUAL expected)
      message(FATAL_ERROR "${what}: ${image} is cut (${size} of ${expected} bytes)")
    endif()
  endforeach()
  file(GLOB partial "${folder}/.*partial*")
  if(partial)
    message(FATAL_ERROR "${what}: temporary files left: ${partial}")
  endif()
endfunction()

# The reference: the batch, no limit.
run(0 ignored ${common} -o ${WORK}/clean/v_%d.mha)

# A single view under the limit: an error naming the file and the short write; no image, no temporary file.
set(LIMITED ON)
run(1 err --size 32 32 --samples 2e4 -q -o ${WORK}/single/one.mha)
if(NOT err MATCHES "cannot write .*one\\.mha: it was written short.*disk full")
  message(FATAL_ERROR "a single view under the limit: unexpected message:\n${err}")
endif()
# A PNG (a format whose header promises no size: the file must read back whole), under a limit below its 477 bytes.
set(limit 300)
run(1 err --size 128 128 --samples 2e4 -q -o ${WORK}/single/one.png)
if(NOT err MATCHES "cannot write .*one\\.png: it does not read back whole")
  message(FATAL_ERROR "a PNG under the limit: unexpected message:\n${err}")
endif()
set(limit 3000)
file(GLOB left "${WORK}/single/*" "${WORK}/single/.*")
if(left)
  message(FATAL_ERROR "a single view under the limit left files: ${left}")
endif()

# The batch: half its views written before (shard 0 of 2, no limit), then the rest under the limit: it stops at
# the first view it writes, with the message, and leaves every image whole.
set(LIMITED OFF)
run(0 ignored ${common} -o ${WORK}/batch/v_%d.mha --shard 0/2)
set(LIMITED ON)
run(1 err ${common} -o ${WORK}/batch/v_%d.mha --resume)
if(NOT err MATCHES "cannot write .*v_1\\.mha: it was written short")
  message(FATAL_ERROR "the batch under the limit: unexpected message:\n${err}")
endif()
no_cut_files("${WORK}/batch" "the batch under the limit")
if(EXISTS "${WORK}/batch/v_1.mha" OR EXISTS "${WORK}/batch/v_1.geometry.txt")
  message(FATAL_ERROR "the batch under the limit left a file of the view it failed")
endif()

# A cut view beside its view file, as an earlier pbdrr left one on a full disk: --resume must not count it done.
file(READ "${WORK}/batch/v_2.mha" bytes HEX)
string(LENGTH "${bytes}" hex_length)
math(EXPR cut_length "${hex_length} * 2 / 3 / 2 * 2")
string(SUBSTRING "${bytes}" 0 ${cut_length} bytes)
string(REGEX REPLACE "([0-9a-f][0-9a-f])" "\\\\x\\1" escaped "${bytes}")
file(REMOVE "${WORK}/batch/v_2.mha")
execute_process(COMMAND /usr/bin/printf "${escaped}" OUTPUT_FILE "${WORK}/batch/v_2.mha")

# The limit lifted: --resume renders what is missing and the cut view, and says how many were done.
set(LIMITED OFF)
run(0 err ${common} -o ${WORK}/batch/v_%d.mha --resume -v)
if(NOT err MATCHES "\\(3 done before: --resume\\)")
  message(FATAL_ERROR "--resume after the limit: it does not count the 3 whole views of shard 0 done:\n${err}")
endif()
no_cut_files("${WORK}/batch" "after --resume")
foreach(k RANGE 7)
  execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files "${WORK}/batch/v_${k}.mha" "${WORK}/clean/v_${k}.mha"
                  RESULT_VARIABLE differ)
  if(differ)
    message(FATAL_ERROR "after --resume, v_${k}.mha differs from the clean run's")
  endif()
  foreach(side batch clean)
    file(STRINGS "${WORK}/${side}/v_${k}.geometry.txt" lines)
    list(REMOVE_AT lines 0) # the line that names the image
    set(${side}_lines "${lines}")
  endforeach()
  if(NOT batch_lines STREQUAL clean_lines)
    message(FATAL_ERROR "after --resume, the view of v_${k} differs from the clean run's")
  endif()
endforeach()
message(STATUS "FullDiskResume: a single view and a batch refused under a file size limit, a cut view re-rendered, "
               "the batch completed by --resume equal to a clean run")
