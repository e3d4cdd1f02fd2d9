# Stand-ins of the three commands of ITK 5.2's CMake/ITKModuleMacros.cmake and CMake/ITKModuleTest.cmake that a
# module's test/CMakeLists.txt calls, for an installed ITK that lacks those files (Debian's). They do what ITK 5.2's
# commands do for this module (written from their documented behaviour, not copied):
#
#   itk_module(NAME [DEPENDS ...] [COMPILE_DEPENDS ...] [PRIVATE_DEPENDS ...] [TEST_DEPENDS ...] [DESCRIPTION text]
#              [EXCLUDE_FROM_DEFAULT] [ENABLE_SHARED])
#     sets itk-module (NAME), itk-module-test (NAME-Test), ITK_MODULE_NAME_DEPENDS (all but TEST_DEPENDS),
#     ITK_MODULE_NAME_TRANSITIVE_DEPENDS (DEPENDS and COMPILE_DEPENDS) and ITK_MODULE_NAME-Test_DEPENDS (NAME and
#     TEST_DEPENDS).
#   itk_module_test()
#     in a module's test/: includes ../itk-module.cmake, calls ITK's itk_module_use() on the test module's
#     dependencies (their include directories) and sets <NAME>-Test_LIBRARIES to their libraries.
#   CreateGoogleTestDriver(KIT KIT_LIBS KitTests)
#     the executable KITGTestDriver from the sources KitTests, linking KIT_LIBS, GTest::GTest and GTest::Main, its
#     tests registered by gtest_discover_tests().
if(COMMAND itk_module_test)
  return() # the real ones
endif()

macro(itk_module _name)
  set(itk-module ${_name})
  set(itk-module-test ${_name}-Test)
  set(ITK_MODULE_${_name}_PUBLIC_DEPENDS "")
  set(_itk_module_compile_depends "")
  set(_itk_module_private_depends "")
  set(ITK_MODULE_${_name}-Test_DEPENDS ${_name})
  set(_doing "")
  foreach(_arg ${ARGN})
    if(_arg MATCHES "^(DEPENDS|COMPILE_DEPENDS|PRIVATE_DEPENDS|TEST_DEPENDS|DESCRIPTION|FACTORY_NAMES)$")
      set(_doing ${_arg})
    elseif(_arg MATCHES "^(EXCLUDE_FROM_DEFAULT|ENABLE_SHARED)$")
      set(_doing "")
    elseif(_doing STREQUAL "DEPENDS")
      list(APPEND ITK_MODULE_${_name}_PUBLIC_DEPENDS ${_arg})
    elseif(_doing STREQUAL "COMPILE_DEPENDS")
      list(APPEND _itk_module_compile_depends ${_arg})
    elseif(_doing STREQUAL "PRIVATE_DEPENDS")
      list(APPEND _itk_module_private_depends ${_arg})
    elseif(_doing STREQUAL "TEST_DEPENDS")
      list(APPEND ITK_MODULE_${_name}-Test_DEPENDS ${_arg})
    elseif(_doing STREQUAL "DESCRIPTION")
      set(_doing "")
    elseif(NOT _doing STREQUAL "FACTORY_NAMES")
      set(_doing "")
      message(AUTHOR_WARNING "Unknown argument [${_arg}]") # as ITK: e.g. a DESCRIPTION cut at a semicolon
    endif()
  endforeach()
  set(ITK_MODULE_${_name}_DEPENDS
    ${ITK_MODULE_${_name}_PUBLIC_DEPENDS} ${_itk_module_compile_depends} ${_itk_module_private_depends})
  set(ITK_MODULE_${_name}_TRANSITIVE_DEPENDS ${ITK_MODULE_${_name}_PUBLIC_DEPENDS} ${_itk_module_compile_depends})
  foreach(_list ITK_MODULE_${_name}_DEPENDS ITK_MODULE_${_name}_TRANSITIVE_DEPENDS ITK_MODULE_${_name}-Test_DEPENDS)
    if(${_list})
      list(SORT ${_list})
    endif()
  endforeach()
endmacro()

macro(itk_module_test)
  include(../itk-module.cmake)
  set(${itk-module-test}_LIBRARIES "")
  itk_module_use(${ITK_MODULE_${itk-module-test}_DEPENDS})
  foreach(_dep IN LISTS ITK_MODULE_${itk-module-test}_DEPENDS)
    list(APPEND ${itk-module-test}_LIBRARIES "${${_dep}_LIBRARIES}")
  endforeach()
endmacro()

function(CreateGoogleTestDriver KIT KIT_LIBS KitTests)
  # ITK's module ITKGoogleTest: its own GoogleTest, or the system's (ITK_USE_SYSTEM_GOOGLETEST) through FindGTest.
  if(NOT TARGET GTest::GTest OR NOT TARGET GTest::Main)
    find_package(GTest REQUIRED)
  endif()
  set(_exe "${KIT}GTestDriver")
  add_executable(${_exe} ${KitTests})
  target_link_libraries(${_exe} ${KIT_LIBS} GTest::GTest GTest::Main)
  include(GoogleTest)
  gtest_discover_tests(${_exe} DISCOVERY_TIMEOUT 15)
endfunction()
