/*=========================================================================
 *
 *  Copyright NumFOCUS and the PointBasedDRR contributors
 *
 *  Licensed under the Apache License, Version 2.0 (the "License");
 *  you may not use this file except in compliance with the License.
 *  You may obtain a copy of the License at
 *
 *         http://www.apache.org/licenses/LICENSE-2.0.txt
 *
 *  Unless required by applicable law or agreed to in writing, software
 *  distributed under the License is distributed on an "AS IS" BASIS,
 *  WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.
 *  See the License for the specific language governing permissions and
 *  limitations under the License.
 *
 *=========================================================================*/
// The README's ten lines: an AP DRR of a CT (HU) in any format ITK reads, written as float line integrals.
//   RenderDRR input.nii.gz output.mha
#include "itkPointBasedDRRImageFilter.h"
#include "itkImageFileReader.h"
#include "itkImageFileWriter.h"

int
main(int argc, char * argv[])
{
  if (argc != 3)
  {
    std::cerr << "usage: " << argv[0] << " CT_VOLUME OUTPUT_IMAGE\n";
    return EXIT_FAILURE;
  }
  try
  {
    using CTType = itk::Image<short, 3>;
    auto ct = itk::ReadImage<CTType>(argv[1]);

    auto drr = itk::PointBasedDRRImageFilter<CTType, itk::Image<float, 2>>::New();
    drr->SetInput(ct);
    drr->GetGeometry()->SetGantryAngleInDegrees(90.0); // AP: source anterior
    drr->GetGeometry()->SetIsocenterToImageCenter(ct); // the centre of the volume
    drr->GetGeometry()->SetDetectorSize({ { 256, 256 } });
    drr->GetGeometry()->SetDetectorSpacing(itk::Vector<double, 2>(1.5)); // mm
    drr->SetNumberOfSamples(20000000);
    drr->SetSeed(1);
    itk::WriteImage(drr->GetOutput(), argv[2]);
  }
  catch (const itk::ExceptionObject & e)
  {
    std::cerr << "error: " << e.GetDescription() << std::endl;
    return EXIT_FAILURE;
  }
  return EXIT_SUCCESS;
}
