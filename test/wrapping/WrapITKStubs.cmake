#[==[ WrapITKStubs.cmake: stand-ins for ITK's wrapping CMake API (WrapITK), so that the module's wrapping/ directory
runs here, where ITK's Python wrapping cannot be built (Debian's ITK 5.2 ships none). include() it from a script run
with `cmake -P`, never from a project: it defines commands with the names of ITK's own.

What it emulates (ITK 5.2's Wrapping/TypedefMacros.cmake and WrapITKTypes.cmake, as the .wrap files of ITK's modules
use them):

- itk_wrap_module(name) ... itk_end_wrap_module(): the wrapper library of one module (checked against the name in
  itk-module.cmake).
- itk_auto_load_submodules(): include()s the submodules named in WRAPPER_SUBMODULE_ORDER, then the other *.wrap files
  of the directory in alphabetical order; itk_load_submodule(name) loads one.
- itk_wrap_class(class [wrap method]) ... itk_wrap_template(mangled_suffix "template arguments") ...
  itk_end_wrap_class(), and itk_wrap_simple_class(class [wrap method]) for a class without template parameters.
  The wrap method (POINTER, POINTER_WITH_SUPERCLASS, ...) is recorded; its SWIG consequences are not emulated.
- itk_wrap_include(header) and WRAPPER_AUTO_INCLUDE_HEADERS (default ON: itk_wrap_class("itk::Foo") includes
  itkFoo.h): the headers the wrapper includes.
- The type variables: ITKM_<T> (the mangled name SWIG and Python use) and ITKT_<T> (the C++ type) of the pixel
  types UC, US, SS, F, D and of the images I<T><dim> of the wrapped scalar types and dimensions
  (ITKM_ISS3 = ISS3, ITKT_ISS3 = "itk::Image< signed short,3 >"); the lists WRAP_ITK_USIGN_INT, WRAP_ITK_SIGN_INT,
  WRAP_ITK_INT, WRAP_ITK_REAL, WRAP_ITK_SCALAR and ITK_WRAP_IMAGE_DIMS. They follow ITK's options ITK_WRAP_<type> and
  ITK_WRAP_IMAGE_DIMS; defaults here: unsigned char, signed short and float on, unsigned short and double off,
  dimensions 2;3. Pass e.g. -DITK_WRAP_signed_short=OFF to run the .wrap files in another configuration.
- What ITK's own modules wrap among the base classes of the module's classes (WRAPITK_STUB_ITK_WRAPPED):
  itk::LightObject, Object, DataObject, ProcessObject; itk::ImageSource of every wrapped scalar image;
  itk::ImageToImageFilter between any two wrapped scalar types of one dimension and between two dimensions within
  one scalar type (ITKCommon's itkImageSource.wrap and itkImageToImageFilterA/B.wrap);
  itk::InterpolateImageFunction of every wrapped scalar image with double coordinates (ITKImageFunction);
  itk::ObjectToObjectMetricBaseTemplate<double> and itk::OptimizerParameterScalesEstimatorTemplate<double>
  (ITKOptimizersv4).

Not emulated: any other ITK wrapping command (itk_wrap_image_filter, itk_wrap_image_filter_combinations,
itk_wrap_filter_dims, UNIQUE, INTERSECTION, ...): a .wrap that calls one stops with CMake's "Unknown CMake command";
add a stand-in here when the module starts using one.

Instead of generating SWIG input, the stubs record every wrapped (class, template arguments) pair, in
WRAPITK_STUB_RECORDS (read it with wrapitk_stub_records()), and are stricter than ITK, reporting what ITK would reject
later (CastXML, SWIG, the compiler, the Python import) or would silently wrap less. Each is an error naming the .wrap
file:
- a header that does not exist in WRAPITK_STUB_INCLUDE_DIRS, or that declares no class of the wrapped name;
- a mangled name that is not the concatenation of the mangled names of the template arguments (ITKM_ and ITKT_ out of
  step), or an argument that is no known type (an undefined ITKM_/ITKT_ variable expands to nothing);
- a class or instance wrapped twice, here or by ITK itself (it would be defined twice in Python);
- itk_wrap_class() ... itk_end_wrap_class() without any itk_wrap_template() (a misspelt list variable; guard the class
  with if() where a configuration can leave it empty);
- a WRAPPER_SUBMODULE_ORDER entry without its .wrap file, a submodule loaded twice, a module name other than
  itk-module.cmake's.

Inputs: WRAPITK_STUB_INCLUDE_DIRS (where the headers are searched), WRAPITK_STUB_MODULE_DIR (the directory of
itk-module.cmake). After the wrapping directory's CMakeLists.txt ran, wrapitk_stub_finish() fails if any error was
reported.
]==]

cmake_policy(VERSION 3.16)

# --- Configuration: ITK's wrapping options ------------------------------------------------------------------------
foreach(option_and_default unsigned_char:ON unsigned_short:OFF signed_short:ON float:ON double:OFF)
  string(REPLACE ":" ";" option_and_default "${option_and_default}")
  list(GET option_and_default 0 option)
  list(GET option_and_default 1 default)
  if(NOT DEFINED ITK_WRAP_${option})
    set(ITK_WRAP_${option} ${default})
  endif()
endforeach()
if(NOT DEFINED ITK_WRAP_IMAGE_DIMS)
  set(ITK_WRAP_IMAGE_DIMS 2 3)
endif()
string(REPLACE "," ";" ITK_WRAP_IMAGE_DIMS "${ITK_WRAP_IMAGE_DIMS}")

# Every type the stubs define: C++ spelling (normalized), mangled name, Python name; parallel lists.
set(WRAPITK_STUB_TYPE_CXX)
set(WRAPITK_STUB_TYPE_MANGLED)
set(WRAPITK_STUB_TYPE_PYTHON)

# _wrapitk_stub_normalize(out type): one spelling of a C++ type: single spaces, none next to <, >, and commas.
function(_wrapitk_stub_normalize out type)
  string(STRIP "${type}" type)
  string(REGEX REPLACE "[ \t\r\n]+" " " type "${type}")
  string(REGEX REPLACE " ?([<>,]) ?" "\\1" type "${type}")
  set(${out} "${type}" PARENT_SCOPE)
endfunction()

macro(_wrapitk_stub_define_type mangled cxx python)
  set(ITKM_${mangled} "${mangled}")
  set(ITKT_${mangled} "${cxx}")
  _wrapitk_stub_normalize(_wrapitk_stub_cxx "${cxx}")
  list(APPEND WRAPITK_STUB_TYPE_CXX "${_wrapitk_stub_cxx}")
  list(APPEND WRAPITK_STUB_TYPE_MANGLED "${mangled}")
  list(APPEND WRAPITK_STUB_TYPE_PYTHON "${python}")
endmacro()

set(_wrapitk_stub_pixel_types "UC:unsigned_char:unsigned char" "US:unsigned_short:unsigned short"
                              "SS:signed_short:signed short" "F:float:float" "D:double:double")
set(WRAP_ITK_USIGN_INT)
set(WRAP_ITK_SIGN_INT)
set(WRAP_ITK_REAL)
foreach(pixel ${_wrapitk_stub_pixel_types})
  string(REPLACE ":" ";" pixel "${pixel}")
  list(GET pixel 0 mangled)
  list(GET pixel 1 option)
  list(GET pixel 2 cxx)
  # The pixel types themselves are defined whatever the options (ITK's ITKM_D is there without ITK_WRAP_double).
  _wrapitk_stub_define_type(${mangled} "${cxx}" "itk.${mangled}")
  if(ITK_WRAP_${option})
    if(mangled MATCHES "^U")
      list(APPEND WRAP_ITK_USIGN_INT ${mangled})
    elseif(mangled MATCHES "^S")
      list(APPEND WRAP_ITK_SIGN_INT ${mangled})
    else()
      list(APPEND WRAP_ITK_REAL ${mangled})
    endif()
  endif()
endforeach()
set(WRAP_ITK_INT ${WRAP_ITK_USIGN_INT} ${WRAP_ITK_SIGN_INT})
set(WRAP_ITK_SCALAR ${WRAP_ITK_INT} ${WRAP_ITK_REAL})
foreach(d ${ITK_WRAP_IMAGE_DIMS})
  foreach(t ${WRAP_ITK_SCALAR})
    _wrapitk_stub_define_type(I${t}${d} "itk::Image< ${ITKT_${t}},${d} >" "itk.Image[itk.${t},${d}]")
  endforeach()
endforeach()

# --- What ITK's own modules wrap, among the base classes of the module's classes: "class|normalized arguments" ----
set(WRAPITK_STUB_ITK_WRAPPED "itk::LightObject|" "itk::Object|" "itk::DataObject|" "itk::ProcessObject|")
foreach(d1 ${ITK_WRAP_IMAGE_DIMS})
  foreach(d2 ${ITK_WRAP_IMAGE_DIMS})
    foreach(t1 ${WRAP_ITK_SCALAR})
      foreach(t2 ${WRAP_ITK_SCALAR})
        if("${d1}" EQUAL "${d2}" OR "${t1}" STREQUAL "${t2}")
          _wrapitk_stub_normalize(arguments "${ITKT_I${t1}${d1}},${ITKT_I${t2}${d2}}")
          list(APPEND WRAPITK_STUB_ITK_WRAPPED "itk::ImageToImageFilter|${arguments}")
        endif()
      endforeach()
    endforeach()
  endforeach()
  foreach(t ${WRAP_ITK_SCALAR})
    _wrapitk_stub_normalize(image "${ITKT_I${t}${d1}}")
    list(APPEND WRAPITK_STUB_ITK_WRAPPED "itk::ImageSource|${image}" "itk::InterpolateImageFunction|${image},double")
  endforeach()
endforeach()
# ITKOptimizersv4's itkObjectToObjectMetricBase.wrap and itkOptimizerParameterScalesEstimator.wrap (double, and the
# real pixel types).
list(APPEND WRAPITK_STUB_ITK_WRAPPED "itk::ObjectToObjectMetricBaseTemplate|double"
     "itk::OptimizerParameterScalesEstimatorTemplate|double")

# --- State and errors ----------------------------------------------------------------------------------------------
set_property(GLOBAL PROPERTY WRAPITK_STUB_RECORDS "")
set_property(GLOBAL PROPERTY WRAPITK_STUB_ERRORS 0)
set_property(GLOBAL PROPERTY WRAPITK_STUB_LOADED "")
set_property(GLOBAL PROPERTY WRAPITK_STUB_SUBMODULE "")
set_property(GLOBAL PROPERTY WRAPITK_STUB_SUBMODULE_INCLUDES "")
set(WRAPPER_AUTO_INCLUDE_HEADERS ON)

# _wrapitk_stub_error(text...): reports an error (the texts concatenated), naming the .wrap file being loaded.
function(_wrapitk_stub_error)
  string(CONCAT text ${ARGV})
  get_property(submodule GLOBAL PROPERTY WRAPITK_STUB_SUBMODULE)
  if(submodule)
    set(text "${submodule}.wrap: ${text}")
  endif()
  message(SEND_ERROR "${text}")
  get_property(errors GLOBAL PROPERTY WRAPITK_STUB_ERRORS)
  math(EXPR errors "${errors} + 1")
  set_property(GLOBAL PROPERTY WRAPITK_STUB_ERRORS ${errors})
endfunction()

# _wrapitk_stub_split_arguments(out arguments): the template arguments, split at the commas outside any <...>.
function(_wrapitk_stub_split_arguments out arguments)
  set(result)
  set(current "")
  set(depth 0)
  string(LENGTH "${arguments}" length)
  if(length GREATER 0)
    math(EXPR last "${length} - 1")
    foreach(i RANGE ${last})
      string(SUBSTRING "${arguments}" ${i} 1 c)
      if(c STREQUAL "<")
        math(EXPR depth "${depth} + 1")
      elseif(c STREQUAL ">")
        math(EXPR depth "${depth} - 1")
      endif()
      if(c STREQUAL "," AND depth EQUAL 0)
        list(APPEND result "${current}")
        set(current "")
      else()
        string(APPEND current "${c}")
      endif()
    endforeach()
  endif()
  list(APPEND result "${current}")
  set(${out} "${result}" PARENT_SCOPE)
endfunction()

# --- The module and its submodules --------------------------------------------------------------------------------
macro(itk_wrap_module library_name)
  set(WRAPPER_LIBRARY_NAME "${library_name}")
  if(NOT DEFINED WRAPPER_LIBRARY_SOURCE_DIR)
    set(WRAPPER_LIBRARY_SOURCE_DIR "${CMAKE_CURRENT_LIST_DIR}")
  endif()
  set(WRAPPER_SUBMODULE_ORDER)
  if(DEFINED WRAPITK_STUB_MODULE_DIR)
    file(READ "${WRAPITK_STUB_MODULE_DIR}/itk-module.cmake" _wrapitk_stub_module)
    if(NOT _wrapitk_stub_module MATCHES "itk_module\\([ \t\r\n]*([A-Za-z0-9_]+)")
      _wrapitk_stub_error("no itk_module(NAME ...) in ${WRAPITK_STUB_MODULE_DIR}/itk-module.cmake")
    elseif(NOT CMAKE_MATCH_1 STREQUAL "${library_name}")
      _wrapitk_stub_error("itk_wrap_module(${library_name}) in a module named ${CMAKE_MATCH_1} (itk-module.cmake)")
    endif()
  endif()
endmacro()

macro(itk_end_wrap_module)
endmacro()

macro(itk_load_submodule submodule)
  get_property(_wrapitk_stub_loaded GLOBAL PROPERTY WRAPITK_STUB_LOADED)
  if("${submodule}" IN_LIST _wrapitk_stub_loaded)
    _wrapitk_stub_error("submodule ${submodule} loaded twice (WRAPPER_SUBMODULE_ORDER names it twice?)")
  elseif(NOT EXISTS "${WRAPPER_LIBRARY_SOURCE_DIR}/${submodule}.wrap")
    _wrapitk_stub_error("WRAPPER_SUBMODULE_ORDER names ${submodule}, but there is no "
                        "${WRAPPER_LIBRARY_SOURCE_DIR}/${submodule}.wrap")
  else()
    set_property(GLOBAL APPEND PROPERTY WRAPITK_STUB_LOADED "${submodule}")
    set_property(GLOBAL PROPERTY WRAPITK_STUB_SUBMODULE "${submodule}")
    set_property(GLOBAL PROPERTY WRAPITK_STUB_SUBMODULE_INCLUDES "")
    include("${WRAPPER_LIBRARY_SOURCE_DIR}/${submodule}.wrap")
    set_property(GLOBAL PROPERTY WRAPITK_STUB_SUBMODULE "")
  endif()
endmacro()

macro(itk_auto_load_submodules)
  set(_wrapitk_stub_submodules ${WRAPPER_SUBMODULE_ORDER})
  file(GLOB _wrapitk_stub_files RELATIVE "${WRAPPER_LIBRARY_SOURCE_DIR}" "${WRAPPER_LIBRARY_SOURCE_DIR}/*.wrap")
  list(SORT _wrapitk_stub_files)
  foreach(_wrapitk_stub_file ${_wrapitk_stub_files})
    string(REGEX REPLACE "\\.wrap$" "" _wrapitk_stub_file "${_wrapitk_stub_file}")
    if(NOT _wrapitk_stub_file IN_LIST WRAPPER_SUBMODULE_ORDER)
      list(APPEND _wrapitk_stub_submodules "${_wrapitk_stub_file}")
    endif()
  endforeach()
  foreach(_wrapitk_stub_submodule ${_wrapitk_stub_submodules})
    itk_load_submodule("${_wrapitk_stub_submodule}")
  endforeach()
endmacro()

# --- Classes -------------------------------------------------------------------------------------------------------
macro(itk_wrap_include header)
  set_property(GLOBAL APPEND PROPERTY WRAPITK_STUB_SUBMODULE_INCLUDES "${header}")
endmacro()

macro(itk_wrap_class class)
  if(DEFINED WRAPPER_CLASS)
    _wrapitk_stub_error("itk_wrap_class(${class}) inside itk_wrap_class(${WRAPPER_CLASS}): "
                        "itk_end_wrap_class() missing")
  endif()
  set(WRAPPER_CLASS "${class}")
  set(WRAPPER_WRAP_METHOD "${ARGN}")
  string(REPLACE "::" "" WRAPPER_SWIG_NAME "${class}")
  set(WRAPPER_TEMPLATES)
  set(_wrapitk_stub_template_count 0)
  if(WRAPPER_AUTO_INCLUDE_HEADERS)
    itk_wrap_include("${WRAPPER_SWIG_NAME}.h")
  endif()
  _wrapitk_stub_check_header("${class}")
endmacro()

macro(itk_wrap_simple_class class)
  itk_wrap_class("${class}" ${ARGN})
  _wrapitk_stub_record("" "")
  set(_wrapitk_stub_template_count -1)
  itk_end_wrap_class()
endmacro()

macro(itk_wrap_template mangled arguments)
  if(NOT DEFINED WRAPPER_CLASS)
    _wrapitk_stub_error("itk_wrap_template(${mangled} ...) outside itk_wrap_class()")
  else()
    _wrapitk_stub_record("${mangled}" "${arguments}")
    math(EXPR _wrapitk_stub_template_count "${_wrapitk_stub_template_count} + 1")
    list(APPEND WRAPPER_TEMPLATES "${mangled} # ${arguments}")
  endif()
endmacro()

macro(itk_end_wrap_class)
  if(NOT DEFINED WRAPPER_CLASS)
    _wrapitk_stub_error("itk_end_wrap_class() without itk_wrap_class()")
  elseif(_wrapitk_stub_template_count EQUAL 0)
    _wrapitk_stub_error("itk_wrap_class(${WRAPPER_CLASS}) wraps no template: a misspelt list variable? Guard the "
                        "class with if() where a configuration of ITK's wrapping can leave it empty")
  endif()
  unset(WRAPPER_CLASS)
endmacro()

# The header of the class (itk_wrap_include or the automatic itk<Class>.h) must exist and declare the class.
function(_wrapitk_stub_check_header class)
  string(REGEX REPLACE ".*::" "" name "${class}")
  get_property(headers GLOBAL PROPERTY WRAPITK_STUB_SUBMODULE_INCLUDES)
  set(found_headers)
  foreach(header ${headers})
    string(REGEX REPLACE "^[<\"](.*)[>\"]$" "\\1" header "${header}")
    set(path)
    foreach(directory ${WRAPITK_STUB_INCLUDE_DIRS})
      if(NOT path AND EXISTS "${directory}/${header}")
        set(path "${directory}/${header}")
      endif()
    endforeach()
    if(NOT path)
      set(directories ${WRAPITK_STUB_INCLUDE_DIRS})
      list(REMOVE_DUPLICATES directories)
      string(REPLACE ";" ", " directories "${directories}")
      _wrapitk_stub_error("${class}: header ${header} not found in ${directories}")
      return()
    endif()
    list(APPEND found_headers "${header}")
    file(STRINGS "${path}" declarations REGEX "^[ \t]*(class|struct)[ \t]")
    foreach(line ${declarations})
      if(line MATCHES "^[ \t]*(class|struct)[ \t]+([A-Za-z_][A-Za-z0-9_]*[ \t]+)?${name}([ \t]*([:{].*)?)?$")
        return()
      endif()
    endforeach()
  endforeach()
  if(found_headers)
    string(REPLACE ";" ", " found_headers "${found_headers}")
    _wrapitk_stub_error("${class}: no class ${name} declared in ${found_headers}")
  else()
    _wrapitk_stub_error("${class}: no header (WRAPPER_AUTO_INCLUDE_HEADERS is off and no itk_wrap_include())")
  endif()
endfunction()

# Records one wrapped class (mangled and arguments empty) or template instance, after checking it.
function(_wrapitk_stub_record mangled arguments)
  get_property(submodule GLOBAL PROPERTY WRAPITK_STUB_SUBMODULE)
  get_property(headers GLOBAL PROPERTY WRAPITK_STUB_SUBMODULE_INCLUDES)
  string(REPLACE ";" "," headers "${headers}")
  set(class "${WRAPPER_CLASS}")
  string(REGEX REPLACE "^itk::" "" python "${class}")
  set(python "itk.${python}")
  set(normalized "")
  if(NOT "${mangled}${arguments}" STREQUAL "")
    _wrapitk_stub_normalize(normalized "${arguments}")
    if(normalized MATCHES "^,|,,|,$|^$|<,|,>")
      _wrapitk_stub_error("${class}: an empty template argument in '${arguments}' (an undefined ITKT_ variable? A "
                          "type ITK does not wrap in this configuration?)")
      return()
    endif()
    _wrapitk_stub_split_arguments(split "${normalized}")
    set(expected "")
    set(python_arguments)
    foreach(argument IN LISTS split)
      list(FIND WRAPITK_STUB_TYPE_CXX "${argument}" index)
      if(index EQUAL -1)
        _wrapitk_stub_error("${class}: template argument '${argument}' of '${arguments}' is no type the stubs "
                            "know (an undefined ITKT_ variable? A type ITK does not wrap in this configuration?)")
        return()
      endif()
      list(GET WRAPITK_STUB_TYPE_MANGLED ${index} argument_mangled)
      list(GET WRAPITK_STUB_TYPE_PYTHON ${index} argument_python)
      string(APPEND expected "${argument_mangled}")
      list(APPEND python_arguments "${argument_python}")
    endforeach()
    if(NOT mangled STREQUAL expected)
      _wrapitk_stub_error("${class}: mangled name '${mangled}' for '${arguments}', whose arguments mangle to "
                          "'${expected}'")
      return()
    endif()
    string(REPLACE ";" ", " python_arguments "${python_arguments}")
    set(python "${python}[${python_arguments}]")
  endif()
  if("${class}|${normalized}" IN_LIST WRAPITK_STUB_ITK_WRAPPED)
    _wrapitk_stub_error("${class}<${normalized}> is wrapped by ITK itself: wrapped twice, it would be defined twice")
    return()
  endif()
  get_property(records GLOBAL PROPERTY WRAPITK_STUB_RECORDS)
  foreach(record ${records})
    string(REPLACE "|" ";" fields "${record}")
    list(GET fields 1 other_class)
    list(GET fields 3 other_mangled)
    list(GET fields 4 other_arguments)
    if(other_class STREQUAL class AND (other_arguments STREQUAL normalized OR other_mangled STREQUAL mangled))
      _wrapitk_stub_error("${class} '${mangled}' (${normalized}) wrapped twice")
      return()
    endif()
  endforeach()
  set_property(GLOBAL APPEND PROPERTY WRAPITK_STUB_RECORDS
               "${submodule}|${class}|${WRAPPER_WRAP_METHOD}|${mangled}|${normalized}|${python}|${headers}")
endfunction()

# --- Results -------------------------------------------------------------------------------------------------------
# wrapitk_stub_records(out): "submodule|class|wrap method|mangled|arguments|Python name|headers" for every wrapped
# class and template instance, in loading order; arguments normalized (no spaces next to <, > and commas), headers
# comma-separated.
function(wrapitk_stub_records out)
  get_property(records GLOBAL PROPERTY WRAPITK_STUB_RECORDS)
  set(${out} "${records}" PARENT_SCOPE)
endfunction()

function(wrapitk_stub_finish)
  get_property(errors GLOBAL PROPERTY WRAPITK_STUB_ERRORS)
  if(errors GREATER 0)
    message(FATAL_ERROR "${errors} error(s) in the .wrap files of ${WRAPPER_LIBRARY_SOURCE_DIR} (above)")
  endif()
endfunction()
