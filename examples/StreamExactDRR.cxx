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

// A CT larger than memory, projected exactly (Siddon through the box model) by streaming it: the reader reads one slab
// of z planes at a time (MetaImage, NRRD and uncompressed NIfTI stream), the filter integrates each slab alone and adds
// the slabs' projections (ExactDRRImageFilter::SetNumberOfStreamDivisions()). Peak memory: one slab and its model.
//
//   StreamExactDRR CT.mha OUTPUT.mha [SLABS]        (SLABS 1: the whole volume at once; default 16)
#include "itkExactDRRImageFilter.h"
#include "itkImageFileReader.h"
#include "itkImageFileWriter.h"

#include <cstdlib>
#include <iostream>
#include <string>

int
main(int argc, char * argv[])
{
  if (argc < 3 || argc > 4)
  {
    std::cerr << "usage: " << argv[0] << " CT_VOLUME OUTPUT_IMAGE [SLABS]\n";
    return EXIT_FAILURE;
  }
  try
  {
    using CTType = itk::Image<short, 3>;
    const unsigned long slabs = argc == 4 ? std::stoul(argv[3]) : 16;
    if (slabs == 0)
    {
      std::cerr << "error: SLABS must be at least 1\n";
      return EXIT_FAILURE;
    }
    auto reader = itk::ImageFileReader<CTType>::New();
    reader->SetFileName(argv[1]);
    reader->UpdateOutputInformation(); // the header only: size, spacing, origin, direction

    auto drr = itk::ExactDRRImageFilter<CTType, itk::Image<float, 2>>::New();
    drr->SetInput(reader->GetOutput());
    drr->SetNumberOfStreamDivisions(static_cast<unsigned int>(slabs));
    drr->GetGeometry()->SetGantryAngleInDegrees(90.0); // AP: source anterior
    drr->GetGeometry()->SetIsocenterToImageCenter(reader->GetOutput());
    drr->GetGeometry()->SetDetectorSize({ { 512, 512 } });
    drr->GetGeometry()->SetDetectorSpacing(itk::Vector<double, 2>(1.0)); // mm
    itk::WriteImage(drr->GetOutput(), argv[2]);
  }
  catch (const std::exception & e)
  {
    std::cerr << "error: " << e.what() << std::endl;
    return EXIT_FAILURE;
  }
  return EXIT_SUCCESS;
}
