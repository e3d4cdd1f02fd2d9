# A batch's views are functions of (seed, view index) alone (issue 17): the same images, bit for bit, from an --angles
# sweep, the same views in a --views file, one --view-index, shards on any thread count, a --resume, and a stack.
#
#   cmake -DEXE=/path/to/pbdrr -DINPUT=volume.mha -DWORK=folder -P BatchEquivalence.cmake
cmake_minimum_required(VERSION 3.16)
foreach(variable EXE INPUT WORK)
  if(NOT ${variable})
    message(FATAL_ERROR "BatchEquivalence: ${variable} is not set")
  endif()
endforeach()
file(REMOVE_RECURSE "${WORK}")
# pbdrr writes into folders that exist (it creates none).
foreach(folder sweep file shards independent poses)
  file(MAKE_DIRECTORY "${WORK}/${folder}")
endforeach()
set(common --size 16 12 --samples 2e4 --seed 5 -q)
set(views 6)
math(EXPR last "${views} - 1")

# run(NAME args...): pbdrr must succeed; its stderr goes to ${NAME}_stderr.
function(run name)
  execute_process(COMMAND "${EXE}" "${INPUT}" ${common} ${ARGN} RESULT_VARIABLE code ERROR_VARIABLE err TIMEOUT 120)
  if(NOT code EQUAL 0)
    string(REPLACE ";" " " shown "${ARGN}")
    message(FATAL_ERROR "pbdrr ${shown}: exit ${code}\n${err}")
  endif()
  set(${name}_stderr "${err}" PARENT_SCOPE)
endfunction()

# same(A B WHAT): the two files are equal, byte for byte.
function(same a b what)
  execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files "${a}" "${b}" RESULT_VARIABLE differ)
  if(differ)
    message(FATAL_ERROR "${what}: ${a} and ${b} differ")
  endif()
endfunction()

# different(A B WHAT): the two files differ (WHAT says what must have made them differ).
function(different a b what)
  execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files "${a}" "${b}" RESULT_VARIABLE differ)
  if(NOT differ)
    message(FATAL_ERROR "${what}: ${a} and ${b} are the same file")
  endif()
endfunction()

# The geometry files beside two images: equal but for their first line, which names the image.
function(same_view a b what)
  foreach(file a b)
    file(STRINGS "${${file}}" lines)
    list(REMOVE_AT lines 0)
    set(${file}_lines "${lines}")
  endforeach()
  if(NOT a_lines STREQUAL b_lines)
    message(FATAL_ERROR "${what}: the views of ${a} and ${b} differ")
  endif()
endfunction()

# The reference: a sweep of 6 views from gantry 15 degrees, 60 degrees apart, on 2 threads.
run(sweep --angles ${views} --angle-step 60 --gantry 15 -o ${WORK}/sweep/v_%d.mha --threads 2)

# The same views in a views file (a view's gantry, two of them named by the file), on 1 thread.
file(WRITE ${WORK}/views.csv "# the sweep's views\ngantry,output\n15,\n75,\n135,named_2.mha\n195,\n255,\n315,named_5.mha\n")
run(file --views ${WORK}/views.csv -o ${WORK}/file/v_%d.mha --threads 1)
foreach(k RANGE ${last})
  set(image ${WORK}/file/v_${k}.mha)
  if(k EQUAL 2 OR k EQUAL 5)
    set(image ${WORK}/file/named_${k}.mha)
  endif()
  same(${WORK}/sweep/v_${k}.mha ${image} "--views view ${k} against the --angles sweep")
endforeach()

# An output folder: the views' files are view_%04d.mha in it.
file(MAKE_DIRECTORY ${WORK}/folder)
run(folder --angles ${views} --angle-step 60 --gantry 15 -o ${WORK}/folder/)
same(${WORK}/sweep/v_3.mha ${WORK}/folder/view_0003.mha "-o FOLDER/'s view 3")

# One view by its index, and the shards, on 1 or 2 threads: the sweep's files.
foreach(k 0 4)
  run(one --angles ${views} --angle-step 60 --gantry 15 -o ${WORK}/one_${k}.mha --view-index ${k} --threads 1)
  same(${WORK}/sweep/v_${k}.mha ${WORK}/one_${k}.mha "--view-index ${k} against the sweep")
  same_view(${WORK}/sweep/v_${k}.geometry.txt ${WORK}/one_${k}.geometry.txt "--view-index ${k}'s view")
endforeach()
foreach(shard 0 1 2)
  math(EXPR threads "1 + ${shard} % 2")
  run(shard --angles ${views} --angle-step 60 --gantry 15 -o ${WORK}/shards/v_%d.mha --shard ${shard}/3
      --threads ${threads})
endforeach()
file(GLOB reference RELATIVE ${WORK}/sweep ${WORK}/sweep/*)
file(GLOB union RELATIVE ${WORK}/shards ${WORK}/shards/* ${WORK}/shards/.*)
list(SORT reference)
list(SORT union)
if(NOT reference STREQUAL union)
  message(FATAL_ERROR "the shards wrote ${union}, the sweep ${reference}")
endif()
foreach(file IN LISTS reference)
  if(file MATCHES "\\.geometry\\.txt$")
    same_view(${WORK}/sweep/${file} ${WORK}/shards/${file} "shard file ${file}")
  else()
    same(${WORK}/sweep/${file} ${WORK}/shards/${file} "shard file ${file}")
  endif()
endforeach()

# --resume renders what is missing, and only that.
file(REMOVE ${WORK}/shards/v_3.mha)
run(resume --angles ${views} --angle-step 60 --gantry 15 -o ${WORK}/shards/v_%d.mha --resume)
same(${WORK}/sweep/v_3.mha ${WORK}/shards/v_3.mha "--resume's view 3")
run(resume_all --angles ${views} --angle-step 60 --gantry 15 -o ${WORK}/shards/v_%d.mha --resume -v)
if(NOT resume_all_stderr MATCHES "0 of 6 views to render \\(6 done before: --resume\\)")
  message(FATAL_ERROR "--resume over a finished batch: ${resume_all_stderr}")
endif()

# New points per view: view k reproduced by its index, and unlike the kept points' view k.
run(independent --angles ${views} --angle-step 60 --gantry 15 -o ${WORK}/independent/v_%d.mha --independent-views)
run(independent_one --angles ${views} --angle-step 60 --gantry 15 -o ${WORK}/independent_4.mha --view-index 4
    --independent-views --threads 1)
same(${WORK}/independent/v_4.mha ${WORK}/independent_4.mha "--independent-views --view-index 4")
different(${WORK}/independent/v_4.mha ${WORK}/sweep/v_4.mha "--independent-views must draw new points, not the kept ones")

# One view twice: the kept points give it twice, new points per view (their seeds from k) two different images.
file(WRITE ${WORK}/twice.csv "gantry\n15\n15\n")
foreach(mode kept independent)
  set(flag "")
  if(mode STREQUAL "independent")
    set(flag --independent-views)
  endif()
  run(twice --views ${WORK}/twice.csv -o ${WORK}/twice_${mode}_%d.mha ${flag})
endforeach()
same(${WORK}/twice_kept_0.mha ${WORK}/twice_kept_1.mha "one view twice, with the kept points")
different(${WORK}/twice_independent_0.mha ${WORK}/twice_independent_1.mha "one view twice, with new points per view")

# RTK's XML: a sweep of mirrored views (RTK's own pixel layout) written with --write-rtk-geometry reads back to the
# same images; a sweep in pbdrr's layout is written with RTK's rows reversed, and reads back mirrored, as RTK lays
# its projections out.
file(WRITE ${WORK}/mirror.txt "mirror 1\n")
file(MAKE_DIRECTORY ${WORK}/rtk_written ${WORK}/rtk_read ${WORK}/rtk_plain)
run(rtk_write --angles ${views} --angle-step 60 --gantry 15 --geometry ${WORK}/mirror.txt
    -o ${WORK}/rtk_written/v_%d.mha --write-rtk-geometry ${WORK}/sweep.xml)
run(rtk_read --rtk-geometry ${WORK}/sweep.xml -o ${WORK}/rtk_read/v_%d.mha --threads 1)
foreach(k RANGE ${last})
  same(${WORK}/rtk_written/v_${k}.mha ${WORK}/rtk_read/v_${k}.mha "RTK's XML, view ${k}, against the sweep that wrote it")
  same_view(${WORK}/rtk_written/v_${k}.geometry.txt ${WORK}/rtk_read/v_${k}.geometry.txt "RTK's XML, view ${k}")
endforeach()
run(rtk_plain --angles ${views} --angle-step 60 --gantry 15 -o ${WORK}/rtk_plain/v_%d.mha
    --write-rtk-geometry ${WORK}/plain.xml --view-index 2)
run(rtk_plain_read --rtk-geometry ${WORK}/plain.xml -o ${WORK}/rtk_plain/read_%d.mha --view-index 2)
file(STRINGS ${WORK}/rtk_plain/v_2.geometry.txt written_mirror REGEX "^mirror")
file(STRINGS ${WORK}/rtk_plain/read_2.geometry.txt read_mirror REGEX "^mirror")
if(NOT written_mirror STREQUAL "mirror 0" OR NOT read_mirror STREQUAL "mirror 1")
  message(FATAL_ERROR "pbdrr's layout written to RTK's XML ('${written_mirror}') must read back as RTK lays "
                      "projections out ('${read_mirror}', expected mirror 1)")
endif()

# Quantum noise: view k's counts are a function of (seed, k), and they change the image.
file(MAKE_DIRECTORY ${WORK}/photons)
run(photons --angles ${views} --angle-step 60 --gantry 15 -o ${WORK}/photons/v_%d.mha --photons 1000)
run(photons_one --angles ${views} --angle-step 60 --gantry 15 -o ${WORK}/photons_4.mha --photons 1000 --view-index 4
    --threads 1)
same(${WORK}/photons/v_4.mha ${WORK}/photons_4.mha "--photons --view-index 4")
different(${WORK}/photons/v_4.mha ${WORK}/sweep/v_4.mha "--photons 1000 must add quantum noise")

# A pose per view: reproduced by its index, and not the pose-less view.
file(WRITE ${WORK}/poses.csv "gantry,tx,ty,tz,rx,ry,rz\n15,0,0,0,0,0,0\n15,4,0,-2,0,0,10\n")
run(poses --views ${WORK}/poses.csv -o ${WORK}/poses/v_%d.mha)
run(pose_one --views ${WORK}/poses.csv -o ${WORK}/pose_1.mha --view-index 1 --threads 1)
same(${WORK}/poses/v_1.mha ${WORK}/pose_1.mha "a posed view by its index")
different(${WORK}/poses/v_1.mha ${WORK}/poses/v_0.mha "the pose tx 4 tz -2 rz 10 must move the CT")

# A stack: one 3D image of the views, slice k the sweep's view k (the pixels after the header, 16 x 12 floats each);
# in transmission too, slice k the transmission view k's file: one conversion for both (DRROutputConversion).
file(MAKE_DIRECTORY ${WORK}/transmission)
run(transmission --angles ${views} --angle-step 60 --gantry 15 -o ${WORK}/transmission/v_%d.mha
    --output-mode transmission)
run(stack_transmission --angles ${views} --angle-step 60 --gantry 15 -o ${WORK}/stack_transmission.mha --stack
    --output-mode transmission)
run(stack --angles ${views} --angle-step 60 --gantry 15 -o ${WORK}/stack.mha --stack)
file(STRINGS ${WORK}/stack.geometry.xml projections REGEX "<Projection>")
list(LENGTH projections projection_count)
if(NOT projection_count EQUAL views)
  message(FATAL_ERROR "the stack's views beside it (stack.geometry.xml) hold ${projection_count} projections, not ${views}")
endif()
foreach(stack_and_views stack:sweep stack_transmission:transmission)
  string(REPLACE ":" ";" stack_and_views "${stack_and_views}")
  list(GET stack_and_views 0 stack)
  list(GET stack_and_views 1 folder)
  file(STRINGS ${WORK}/${stack}.mha dimensions REGEX "^DimSize")
  if(NOT dimensions STREQUAL "DimSize = 16 12 6")
    message(FATAL_ERROR "${stack} is ${dimensions}, not 16 x 12 x 6")
  endif()
  file(SIZE ${WORK}/${stack}.mha stack_size)
  math(EXPR stack_pixels "${stack_size} - 16 * 12 * 4 * ${views}")
  foreach(k RANGE ${last})
    file(SIZE ${WORK}/${folder}/v_${k}.mha view_size)
    math(EXPR view_header "${view_size} - 16 * 12 * 4")
    math(EXPR offset "${stack_pixels} + ${k} * 16 * 12 * 4")
    file(READ ${WORK}/${stack}.mha slice OFFSET ${offset} LIMIT 768 HEX)
    file(READ ${WORK}/${folder}/v_${k}.mha pixels OFFSET ${view_header} LIMIT 768 HEX)
    if(NOT slice STREQUAL pixels)
      message(FATAL_ERROR "slice ${k} of ${stack} is not view ${k} of ${folder}/")
    endif()
  endforeach()
endforeach()
# A manifest of two volumes (the sweep, and the views file with a pose column), in two shards cutting across them:
# each volume's files are its single batch's.
file(MAKE_DIRECTORY ${WORK}/manifest_sweep ${WORK}/manifest_poses)
file(WRITE ${WORK}/manifest.csv "volume,output,views,angles,angle_step,gantry\n"
                                "${INPUT},manifest_sweep/v_%d.mha,,${views},60,15\n"
                                "${INPUT},manifest_poses/v_%d.mha,poses.csv,,,\n")
foreach(shard 0 1)
  execute_process(COMMAND "${EXE}" --manifest ${WORK}/manifest.csv ${common} --shard ${shard}/2 --threads 1
                  RESULT_VARIABLE code ERROR_VARIABLE err TIMEOUT 120)
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "pbdrr --manifest --shard ${shard}/2: exit ${code}\n${err}")
  endif()
endforeach()
foreach(k RANGE ${last})
  same(${WORK}/sweep/v_${k}.mha ${WORK}/manifest_sweep/v_${k}.mha "the manifest's sweep, view ${k}")
endforeach()
foreach(k 0 1)
  same(${WORK}/poses/v_${k}.mha ${WORK}/manifest_poses/v_${k}.mha "the manifest's views file, view ${k}")
endforeach()

# A run killed midway leaves whole files, or none, under the views' names (each is written under a hidden temporary
# name and renamed), and --resume completes it: the files of an uninterrupted run.
set(long --angles 300 --angle-step 1.2 --size 48 48 --spacing 0.4 0.4)
file(MAKE_DIRECTORY ${WORK}/whole ${WORK}/killed)
run(whole ${long} -o ${WORK}/whole/v_%d.mha)
execute_process(COMMAND "${EXE}" "${INPUT}" ${common} ${long} -o ${WORK}/killed/v_%d.mha TIMEOUT 0.3
                RESULT_VARIABLE killed_code)
file(GLOB written RELATIVE ${WORK}/killed ${WORK}/killed/v_*)
list(LENGTH written killed_count)
foreach(file IN LISTS written)
  if(file MATCHES "\\.mha$")
    same(${WORK}/whole/${file} ${WORK}/killed/${file} "a file of the killed run (exit ${killed_code})")
  endif()
endforeach()
run(completed ${long} -o ${WORK}/killed/v_%d.mha --resume)
foreach(k RANGE 299)
  same(${WORK}/whole/v_${k}.mha ${WORK}/killed/v_${k}.mha "view ${k} after the killed run's --resume")
endforeach()
message(STATUS "the killed run (exit '${killed_code}') left ${killed_count} whole files; --resume completed them")

message(STATUS "every batch form gave the sweep's images, bit for bit")

# --accuracy alone chooses at view 0 for every view (here kept points, drawn at view 0 in the number its estimate
# asks): the shards without view 0 give the sweep's images, bit for bit, on 1 or 2 threads.
file(MAKE_DIRECTORY ${WORK}/accuracy ${WORK}/accuracy_shards)
set(accuracy --size 16 12 --accuracy 12 --seed 5 --angles ${views} --angle-step 60 --gantry 15)
execute_process(COMMAND "${EXE}" "${INPUT}" ${accuracy} -o ${WORK}/accuracy/v_%d.mha -v --threads 2
                RESULT_VARIABLE code ERROR_VARIABLE accuracy_stderr TIMEOUT 120)
if(NOT code EQUAL 0 OR NOT accuracy_stderr MATCHES "accuracy: chose points [0-9]+,")
  message(FATAL_ERROR "--accuracy 12 over ${views} views must choose kept points: exit ${code}\n${accuracy_stderr}")
endif()
foreach(shard 1 2)
  math(EXPR threads "1 + ${shard} % 2")
  execute_process(COMMAND "${EXE}" "${INPUT}" ${accuracy} -o ${WORK}/accuracy_shards/v_%d.mha --shard ${shard}/3
                          --threads ${threads} RESULT_VARIABLE code ERROR_VARIABLE err TIMEOUT 120)
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "--accuracy --shard ${shard}/3: exit ${code}\n${err}")
  endif()
endforeach()
foreach(k 1 2 4 5) # shard K/3 renders the views k with k % 3 = K
  same(${WORK}/accuracy/v_${k}.mha ${WORK}/accuracy_shards/v_${k}.mha "--accuracy: shard view ${k} against the sweep")
endforeach()
