# Installs this build into PREFIX, then configures, builds and runs test/install/Downstream against the installed
# tree alone (find_package(PointBasedDRR) with CMAKE_PREFIX_PATH=PREFIX), and runs the installed pbdrr:
#   cmake -DBUILD_DIR=... -DITK_DIR=... -DPREFIX=... -DDOWNSTREAM_SOURCE=... -DDOWNSTREAM_BINARY=... -P InstallAndBuildDownstream.cmake
cmake_minimum_required(VERSION 3.16)

include(${CMAKE_CURRENT_LIST_DIR}/RunStep.cmake)

file(REMOVE_RECURSE "${PREFIX}" "${DOWNSTREAM_BINARY}")
run("install" ${CMAKE_COMMAND} --install "${BUILD_DIR}" --prefix "${PREFIX}")
foreach(file include/PointBasedDRR/itkPointBasedDRRImageFilter.h include/PointBasedDRR/PointBasedDRRExport.h
             lib/cmake/PointBasedDRR/PointBasedDRRConfig.cmake lib/cmake/PointBasedDRR/PointBasedDRRTargets.cmake
             bin/pbdrr)
  if(NOT EXISTS "${PREFIX}/${file}")
    message(FATAL_ERROR "the install tree lacks ${file}")
  endif()
endforeach()
# The source tree must not be reachable: only what was installed.
run("configure the downstream project" ${CMAKE_COMMAND} -S "${DOWNSTREAM_SOURCE}" -B "${DOWNSTREAM_BINARY}"
    -DCMAKE_BUILD_TYPE=Release "-DCMAKE_PREFIX_PATH=${PREFIX}" "-DITK_DIR=${ITK_DIR}")
run("build the downstream project" ${CMAKE_COMMAND} --build "${DOWNSTREAM_BINARY}")
file(STRINGS "${DOWNSTREAM_BINARY}/CMakeCache.txt" found REGEX "^PointBasedDRR_DIR:")
if(NOT found MATCHES "${PREFIX}/lib/cmake/PointBasedDRR")
  message(FATAL_ERROR "the downstream project found PointBasedDRR elsewhere: ${found}")
endif()
run("run the downstream program" "${DOWNSTREAM_BINARY}/Downstream")
run("run the installed pbdrr" "${PREFIX}/bin/pbdrr" --version)
