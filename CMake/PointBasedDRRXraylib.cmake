# xraylib (Debian: libxrl-dev, xraylib 4.0): photon cross sections of elements, chemical formulas and the NIST compound
# list, used by DRRMaterialTable and DRRXRaySpectrum (the library links it PRIVATE). Included by src/ and test/ (the
# tests compare the library with xraylib called directly). Sets PointBasedDRR_XRAYLIB_INCLUDE_DIR and
# PointBasedDRR_XRAYLIB_LIBRARY (full paths: an exported static PointBasedDRR then names the library itself).
if(NOT PointBasedDRR_XRAYLIB_LIBRARY OR NOT PointBasedDRR_XRAYLIB_INCLUDE_DIR)
  find_package(PkgConfig QUIET)
  if(PKG_CONFIG_FOUND)
    pkg_check_modules(PC_LIBXRL QUIET libxrl)
  endif()
  find_path(PointBasedDRR_XRAYLIB_INCLUDE_DIR xraylib.h HINTS ${PC_LIBXRL_INCLUDE_DIRS} PATH_SUFFIXES xraylib
            DOC "Directory of xraylib.h (Debian: /usr/include/xraylib)")
  find_library(PointBasedDRR_XRAYLIB_LIBRARY NAMES xrl HINTS ${PC_LIBXRL_LIBRARY_DIRS}
               DOC "The xraylib library (libxrl)")
endif()
if(NOT PointBasedDRR_XRAYLIB_LIBRARY OR NOT PointBasedDRR_XRAYLIB_INCLUDE_DIR)
  message(FATAL_ERROR "PointBasedDRR needs xraylib (Debian: apt-get install libxrl-dev; or set "
                      "PointBasedDRR_XRAYLIB_INCLUDE_DIR and PointBasedDRR_XRAYLIB_LIBRARY)")
endif()
