# Runs the module's wrapping/ directory (its CMakeLists.txt and every .wrap file) with the stand-ins of
# WrapITKStubs.cmake and writes what it wraps:
#
#   cmake -DWRAPPING_DIR=<module>/wrapping -DMODULE_DIR=<module> -DINCLUDE_DIRS="dir1|dir2|..."
#         [-DOUTPUT_CXX=file.cxx] [-DOUTPUT_TABLE=file.md] [-DITK_WRAP_<type>=ON|OFF ...]
#         [-DITK_WRAP_IMAGE_DIMS=2,3] -P GenerateWrappedSetTest.cmake
#
# OUTPUT_CXX: one GoogleTest translation unit that explicitly instantiates every wrapped template instance (what SWIG
# would compile) and has one test per wrapped class or instance, which runs it once (PointBasedDRRWrappedSetTest.h).
# OUTPUT_TABLE: the Markdown table of the wrapped set that docs/wrapping.md holds. Without outputs, it only checks the
# .wrap files (in the configuration given). Fails, writing nothing, on any error the stubs report.

cmake_policy(VERSION 3.16)
foreach(input WRAPPING_DIR MODULE_DIR INCLUDE_DIRS)
  if(NOT DEFINED ${input})
    message(FATAL_ERROR "GenerateWrappedSetTest.cmake: -D${input}=... missing")
  endif()
endforeach()
string(REPLACE "|" ";" WRAPITK_STUB_INCLUDE_DIRS "${INCLUDE_DIRS}")
set(WRAPITK_STUB_MODULE_DIR "${MODULE_DIR}")
set(WRAPPER_LIBRARY_SOURCE_DIR "${WRAPPING_DIR}")

include("${CMAKE_CURRENT_LIST_DIR}/WrapITKStubs.cmake")
include("${WRAPPING_DIR}/CMakeLists.txt")
wrapitk_stub_finish()
wrapitk_stub_records(records)

set(includes)
set(instantiations "")
set(wrapped_here "")
set(tests "")
set(table "| .wrap file | C++ class | SWIG name | Python |\n|---|---|---|---|\n")
set(instances 0)
set(classes 0)
foreach(record ${records})
  string(REPLACE "|" ";" fields "${record}")
  list(GET fields 0 submodule)
  list(GET fields 1 class)
  list(GET fields 3 mangled)
  list(GET fields 4 arguments)
  list(GET fields 5 python)
  list(GET fields 6 headers)
  string(REPLACE "," ";" headers "${headers}")
  foreach(header ${headers})
    if(NOT header IN_LIST includes)
      list(APPEND includes "${header}")
    endif()
  endforeach()
  string(REPLACE "::" "" swig_name "${class}${mangled}")
  if(arguments STREQUAL "")
    set(type "${class}")
    math(EXPR classes "${classes} + 1")
  else()
    string(REPLACE ">,itk::" ">, itk::" arguments "${arguments}")
    string(REPLACE ">,double" ">, double" arguments "${arguments}")
    set(type "${class}<${arguments}>")
    string(APPEND instantiations "template class ${type};\n")
    math(EXPR instances "${instances} + 1")
  endif()
  string(APPEND wrapped_here "template <>\nstruct WrappedHere<${type}> : std::true_type\n{};\n")
  string(APPEND tests "// wrapping/${submodule}.wrap: ${python}\nTEST(PointBasedDRRWrappedSet, ${swig_name})\n{\n"
                      "  PointBasedDRRWrappedSet::Exercise<${type}>(\"${class}\");\n}\n\n")
  string(APPEND table "| `${submodule}.wrap` | `${type}` | `${swig_name}` | `${python}` |\n")
endforeach()

# What ITK's own modules wrap (the superclass check stops there).
set(wrapped_by_itk "")
foreach(entry ${WRAPITK_STUB_ITK_WRAPPED})
  string(REPLACE "|" ";" fields "${entry}")
  list(GET fields 0 class)
  list(LENGTH fields length)
  set(type "${class}")
  if(length GREATER 1)
    list(GET fields 1 arguments)
    if(NOT arguments STREQUAL "")
      set(type "${class}<${arguments}>")
    endif()
  endif()
  string(APPEND wrapped_by_itk "template <>\nstruct WrappedByITK<${type}> : std::true_type\n{};\n")
endforeach()

math(EXPR count "${classes} + ${instances}")
message(STATUS "wrapping/ of ${WRAPPER_LIBRARY_NAME}: ${count} wrapped (${classes} classes, ${instances} template "
               "instances) with ITK_WRAP_IMAGE_DIMS ${ITK_WRAP_IMAGE_DIMS}, WRAP_ITK_SCALAR ${WRAP_ITK_SCALAR}")

if(DEFINED OUTPUT_CXX)
  set(cxx "// Generated from ${WRAPPING_DIR} by ${CMAKE_CURRENT_LIST_FILE}: do not edit.\n")
  string(APPEND cxx "// Every class and template instance the .wrap files name, explicitly instantiated and run "
                    "once.\n\n")
  foreach(header ${includes})
    string(APPEND cxx "#include \"${header}\"\n")
  endforeach()
  string(APPEND cxx "#include \"PointBasedDRRWrappedSetTest.h\"\n\n")
  string(APPEND cxx "// What SWIG would compile: every wrapped template instance, all its members.\n"
                    "${instantiations}\n")
  string(APPEND cxx "namespace PointBasedDRRWrappedSet\n{\n${wrapped_here}\n${wrapped_by_itk}} // namespace "
                    "PointBasedDRRWrappedSet\n\n${tests}")
  file(WRITE "${OUTPUT_CXX}" "${cxx}")
endif()
if(DEFINED OUTPUT_TABLE)
  file(WRITE "${OUTPUT_TABLE}" "${table}")
endif()
