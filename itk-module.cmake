# One sentence, not the whole README: itk_module() takes DESCRIPTION as one argument, and every semicolon of a long
# Markdown file would split it (ITK keeps the first piece and warns about the rest).
set(DOCUMENTATION "Digitally reconstructed radiographs of CT volumes by unbiased Monte Carlo point sampling, with \
standard-error images and exact Siddon and trilinear reference projectors (see README.md).")

itk_module(PointBasedDRR
  DEPENDS
    ITKCommon
    ITKTransform
    ITKImageGrid
    ITKOptimizers
    ITKOptimizersv4
  COMPILE_DEPENDS
    ITKImageFunction
  PRIVATE_DEPENDS
    ITKIOXML
    ITKZLIB
  TEST_DEPENDS
    ITKTestKernel
    ITKGoogleTest
  DESCRIPTION
    "${DOCUMENTATION}"
  EXCLUDE_FROM_DEFAULT
  ENABLE_SHARED
)
