# Install rules and the exported CMake package of the stand-alone build (included by the top-level CMakeLists.txt):
#   cmake --install build --prefix /opt/pbdrr
# installs include/PointBasedDRR/*.h(xx), lib/libPointBasedDRR.a, bin/pbdrr and lib/cmake/PointBasedDRR/ (config,
# version, targets), so that another project does find_package(PointBasedDRR) and links PointBasedDRR::PointBasedDRR.
# Inside an ITK tree, ITK's module machinery (itk_module_impl) installs and exports the module instead.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(PointBasedDRR_INSTALL_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/PointBasedDRR)

install(TARGETS PointBasedDRR EXPORT PointBasedDRRTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/PointBasedDRR)
file(GLOB PointBasedDRR_HEADERS ${PROJECT_SOURCE_DIR}/include/*.h ${PROJECT_SOURCE_DIR}/include/*.hxx)
install(FILES ${PointBasedDRR_HEADERS} ${PROJECT_BINARY_DIR}/include/PointBasedDRRExport.h
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/PointBasedDRR)
# The installed pbdrr keeps the run path of the libraries it links from outside this build: an ITK built from source
# (ITK_DIR a build tree, as scripts/build-itk.sh makes it) is in no system directory. (Debian's ITK, in the linker's
# implicit directories, adds none.)
set_target_properties(pbdrr PROPERTIES INSTALL_RPATH_USE_LINK_PATH ON)
install(TARGETS pbdrr RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})

install(EXPORT PointBasedDRRTargets NAMESPACE PointBasedDRR:: DESTINATION ${PointBasedDRR_INSTALL_CMAKE_DIR})

configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/PointBasedDRRConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/install/PointBasedDRRConfig.cmake
                              INSTALL_DESTINATION ${PointBasedDRR_INSTALL_CMAKE_DIR}
                              PATH_VARS CMAKE_INSTALL_INCLUDEDIR)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/install/PointBasedDRRConfigVersion.cmake
                                 VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/install/PointBasedDRRConfig.cmake
              ${PROJECT_BINARY_DIR}/install/PointBasedDRRConfigVersion.cmake
        DESTINATION ${PointBasedDRR_INSTALL_CMAKE_DIR})
