# pbdrr built on its own against the installed module (issue 40, item 5): installs this build into PREFIX, then
# configures and builds apps/pbdrr as a project of its own (find_package(PointBasedDRR) with CMAKE_PREFIX_PATH=PREFIX),
# checks that no compile line reaches the module's include/ or src/ (only the installed headers), and runs the pbdrr
# it built on a small volume:
#   cmake -DBUILD_DIR=... -DITK_DIR=... -DPREFIX=... -DSOURCE_DIR=... -DPBDRR_BINARY=... -DVOLUME=... -P BuildPbdrrAgainstInstall.cmake
cmake_minimum_required(VERSION 3.16)

include(${CMAKE_CURRENT_LIST_DIR}/RunStep.cmake)

file(REMOVE_RECURSE "${PREFIX}" "${PBDRR_BINARY}")
run("install" ${CMAKE_COMMAND} --install "${BUILD_DIR}" --prefix "${PREFIX}")
run("configure pbdrr against the installed module" ${CMAKE_COMMAND} -S "${SOURCE_DIR}/apps/pbdrr" -B "${PBDRR_BINARY}"
    -DCMAKE_BUILD_TYPE=Release "-DCMAKE_PREFIX_PATH=${PREFIX}" "-DITK_DIR=${ITK_DIR}")
file(STRINGS "${PBDRR_BINARY}/CMakeCache.txt" found REGEX "^PointBasedDRR_DIR:")
if(NOT found MATCHES "${PREFIX}/lib/cmake/PointBasedDRR")
  message(FATAL_ERROR "pbdrr found PointBasedDRR elsewhere: ${found}")
endif()
file(GLOB_RECURSE flag_files "${PBDRR_BINARY}/*flags.make")
foreach(flags ${flag_files})
  file(READ "${flags}" text)
  foreach(folder include src)
    string(FIND "${text}" "-I${SOURCE_DIR}/${folder}" at)
    if(NOT at EQUAL -1)
      message(FATAL_ERROR "${flags} reaches the module's ${folder}/: pbdrr must build on the installed headers alone")
    endif()
  endforeach()
endforeach()
run("build pbdrr" ${CMAKE_COMMAND} --build "${PBDRR_BINARY}" -j 2)
run("run it" "${PBDRR_BINARY}/pbdrr" --version)
run("render with it" "${PBDRR_BINARY}/pbdrr" "${VOLUME}" -o "${PBDRR_BINARY}/out.mha" --size 16 16 --samples 1e4 -q)
if(NOT EXISTS "${PBDRR_BINARY}/out.mha")
  message(FATAL_ERROR "the pbdrr built against the installed module wrote no image")
endif()
