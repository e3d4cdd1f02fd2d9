#include "itkPointBasedDRRImageFilter.h"
#include "itkExactDRRImageFilter.h"
#include "itkImage.h"
#include "gtest/gtest.h"
#include <cmath>

TEST(Smoke, PointBasedMatchesExactOnSmallPhantom)
{
  using VolumeType = itk::Image<short, 3>;
  using ProjectionType = itk::Image<float, 2>;
  auto                 volume = VolumeType::New();
  VolumeType::SizeType size = { { 8, 9, 7 } };
  volume->SetRegions(size);
  VolumeType::SpacingType spacing;
  spacing[0] = 2;
  spacing[1] = 3;
  spacing[2] = 2.5;
  volume->SetSpacing(spacing);
  VolumeType::PointType origin;
  origin[0] = -7;
  origin[1] = -12;
  origin[2] = -7.5;
  volume->SetOrigin(origin);
  volume->Allocate();
  unsigned int s = 1;
  for (auto * p = volume->GetBufferPointer();
       p != volume->GetBufferPointer() + volume->GetBufferedRegion().GetNumberOfPixels();
       ++p)
  {
    s = s * 1103515245u + 12345u;
    *p = static_cast<short>(-1000 + ((s >> 16) % 5) * 500);
  }
  auto exact = itk::ExactDRRImageFilter<VolumeType, ProjectionType>::New();
  exact->SetInput(volume);
  exact->GetGeometry()->SetSourceToIsocenterDistance(60);
  exact->GetGeometry()->SetSourceToDetectorDistance(100);
  itk::Size<2> det = { { 10, 8 } };
  exact->GetGeometry()->SetDetectorSize(det);
  itk::Vector<double, 2> dsp;
  dsp[0] = 4;
  dsp[1] = 5;
  exact->GetGeometry()->SetDetectorSpacing(dsp);
  exact->SetRaysPerPixelSide(16);
  exact->Update();
  auto drr = itk::PointBasedDRRImageFilter<VolumeType, ProjectionType>::New();
  drr->SetInput(volume);
  drr->SetGeometry(exact->GetGeometry());
  drr->SetNumberOfSamples(20000000);
  drr->Update();
  double maxZ = 0, sumRef = 0, sumEst = 0;
  for (unsigned p = 0; p < 80; ++p)
  {
    const double ref = exact->GetOutput()->GetBufferPointer()[p];
    const double est = drr->GetOutput()->GetBufferPointer()[p];
    const double se = drr->GetStandardErrorOutput()->GetBufferPointer()[p];
    sumRef += ref;
    sumEst += est;
    if (se > 0)
      maxZ = std::max(maxZ, std::abs(est - ref) / se);
    if (p < 12)
      std::cout << ref << " " << est << " +- " << se << "\n";
  }
  std::cout << "sum ratio " << sumEst / sumRef << " maxZ " << maxZ << "\n";
  EXPECT_LT(maxZ, 4.5);
}
