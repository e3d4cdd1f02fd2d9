# The ITK the module's programs use (pbdrr, the tests, the examples, the benchmarks): the modules the library computes
# with and those that read and write images and register, with ITK 5's and ITK 6's ways to reach them. Sets
# PointBasedDRR_ITK_PROGRAM_LIBRARIES, what every program links. Included by the top CMakeLists.txt and by
# apps/pbdrr/CMakeLists.txt when pbdrr is built on its own against an installed PointBasedDRR.
find_package(ITK 5.2 REQUIRED COMPONENTS
  ITKCommon
  ITKTransform
  ITKImageFunction
  ITKImageGrid
  ITKImageIntensity
  ITKOptimizers
  ITKOptimizersv4
  ITKRegistrationCommon
  ITKIOImageBase
  ITKIOGDCM
  ITKGDCM
  ITKIOMeta
  ITKIONRRD
  ITKIONIFTI
  ITKIOPNG
  ITKIOTIFF
  ITKIOTransformBase
  ITKIOTransformInsightLegacy
  ITKIOXML
  ITKZLIB)
if(ITK_VERSION_MAJOR LESS 6)
  # ITK 5: the include directories (5.2's imported targets have none), ITK_REQUIRED_*_FLAGS and the IO factory
  # registration (ITK_IMAGEIO_FACTORY_REGISTER_MANAGER and its generated header).
  include(${ITK_USE_FILE})
  set(PointBasedDRR_ITK_PROGRAM_LIBRARIES ${ITK_LIBRARIES})
else()
  # ITK 6 deprecates UseITK.cmake (an AUTHOR_WARNING; an error under ITK_FUTURE_LEGACY_REMOVE). Its modules'
  # interface targets (ITK_INTERFACE_LIBRARIES, ITK::<module>Module) carry their include directories, GDCM's and
  # those of header-only modules too; the factory registration headers are generated here and reach the programs
  # through the meta-module targets ITK::ITKImageIO and ITK::ITKTransformIO (their compile definitions).
  separate_arguments(PointBasedDRR_ITK_REQUIRED_CXX_FLAGS UNIX_COMMAND "${ITK_REQUIRED_CXX_FLAGS}")
  add_compile_options(${PointBasedDRR_ITK_REQUIRED_CXX_FLAGS})
  itk_generate_factory_registration()
  set(PointBasedDRR_ITK_PROGRAM_LIBRARIES ${ITK_INTERFACE_LIBRARIES})
  foreach(meta_module ITK::ITKImageIO ITK::ITKTransformIO)
    if(TARGET ${meta_module})
      list(APPEND PointBasedDRR_ITK_PROGRAM_LIBRARIES ${meta_module})
    endif()
  endforeach()
endif()
