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
// Built against the installed headers and library only: renders a phantom with both filters in a parallel beam that
// catches every point. There the point-based image sum is exactly M / a (every point lands with weight 1; M, the
// attenuation mass, computed here by hand) and the exact projector's sum is the same integral by a midpoint rule.
// Exit code 0 if all three agree.
#include "itkExactDRRImageFilter.h"
#include "itkPointBasedDRRImageFilter.h"
#include "itkImageRegionConstIterator.h"

#include <cmath>
#include <iostream>
#include <numeric>

int
main()
{
  using VolumeType = itk::Image<short, 3>;
  using ProjectionType = itk::Image<float, 2>;
  auto volume = VolumeType::New();
  volume->SetRegions(VolumeType::SizeType{ { 10, 8, 6 } });
  volume->SetSpacing(itk::Vector<double, 3>(2.0)); // mm
  volume->Allocate();
  for (itk::IndexValueType k = 0; k < 6; ++k)
  {
    for (itk::IndexValueType j = 0; j < 8; ++j)
    {
      for (itk::IndexValueType i = 0; i < 10; ++i)
      {
        volume->SetPixel({ { i, j, k } }, static_cast<short>((i + 2 * j + 3 * k) % 4 == 0 ? 1000 : 0)); // HU
      }
    }
  }
  auto geometry = itk::DRRProjectionGeometry::New();
  geometry->SetProjection(itk::PointBasedDRREnums::Projection::Parallel);
  geometry->SetIsocenter(volume->GetOrigin() + itk::Vector<double, 3>(5.0)); // near the volume centre, mm
  geometry->SetDetectorSize({ { 32, 32 } });
  geometry->SetDetectorSpacing(itk::Vector<double, 2>(1.5)); // mm: the detector covers the volume's shadow

  double mass = 0.0; // mm^2: mu = mu_water (1 + HU / 1000), 0.02059 /mm at 60 keV, times the voxel volume (8 mm^3)
  for (itk::ImageRegionConstIterator<VolumeType> it(volume, volume->GetLargestPossibleRegion()); !it.IsAtEnd(); ++it)
  {
    mass += 0.02059 * (1.0 + it.Get() / 1000.0) * 8.0;
  }
  const double pixelArea = 1.5 * 1.5; // mm^2
  double       sums[2] = { 0.0, 0.0 };
  try
  {
    auto pointBased = itk::PointBasedDRRImageFilter<VolumeType, ProjectionType>::New();
    pointBased->SetInput(volume);
    pointBased->SetGeometry(geometry);
    pointBased->SetNumberOfSamples(200000);
    auto exact = itk::ExactDRRImageFilter<VolumeType, ProjectionType>::New();
    exact->SetInput(volume);
    exact->SetGeometry(geometry);
    exact->SetRaysPerPixelSide(8);
    ProjectionType::Pointer images[2] = { pointBased->GetOutput(), exact->GetOutput() };
    pointBased->Update();
    exact->Update();
    for (unsigned int m = 0; m < 2; ++m)
    {
      const float * buffer = images[m]->GetBufferPointer();
      sums[m] = std::accumulate(buffer, buffer + images[m]->GetBufferedRegion().GetNumberOfPixels(), 0.0);
    }
  }
  catch (const itk::ExceptionObject & e)
  {
    std::cerr << "Downstream: " << e.GetDescription() << std::endl;
    return 1;
  }
  std::cout << "Downstream: image sums, M / a " << mass / pixelArea << ", point-based " << sums[0] << ", exact "
            << sums[1] << std::endl;
  // Point-based: M / a up to float rounding of 1024 pixels. Exact: a midpoint rule of 8 x 8 rays per 1.5 mm pixel
  // over 2 mm voxels, within 1% of the integral.
  const bool pointBasedExact = std::abs(sums[0] - mass / pixelArea) < 1e-5 * mass / pixelArea;
  const bool exactClose = std::abs(sums[1] - mass / pixelArea) < 0.01 * mass / pixelArea;
  return pointBasedExact && exactClose ? 0 : 1;
}
