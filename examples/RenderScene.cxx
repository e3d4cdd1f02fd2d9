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
// What a scene requires, and only that (docs/design.md sections 12 to 14): one AP view of a CT four ways.
//   RenderScene CT_VOLUME_OR_DICOM_DIRECTORY OUTPUT_PREFIX [SAMPLES]
// writes OUTPUT_PREFIX_line_integral.mha (mu at 60 keV), _bone.mha (the bone label alone: labels from HU thresholds,
// standing in for a segmentation, written as _labels.mha for pbdrr --labels), _70kvp.mha and _120kvp.mha (polychromatic
// -ln T through DeepDRR's materials and Kramers' spectrum, with 10^4 photons per pixel of quantum noise).
#include "itkDRRPolychromaticImageFilter.h"
#include "itkDRRQuantumNoiseImageFilter.h"
#include "itkGDCMImageIO.h"
#include "itkGDCMSeriesFileNames.h"
#include "itkImageFileReader.h"
#include "itkImageFileWriter.h"
#include "itkImageSeriesReader.h"
#include "itkPointBasedDRRImageFilter.h"
#include "itksys/SystemTools.hxx"

namespace
{
using CTType = itk::Image<short, 3>;
using ProjectionType = itk::Image<float, 2>;
using DRRType = itk::PointBasedDRRImageFilter<CTType, ProjectionType>;

/** A DICOM series directory (its first series) or any volume ITK reads. */
CTType::Pointer
ReadCT(const std::string & input)
{
  if (!itksys::SystemTools::FileIsDirectory(input))
  {
    return itk::ReadImage<CTType>(input);
  }
  auto names = itk::GDCMSeriesFileNames::New();
  names->SetUseSeriesDetails(true);
  names->SetDirectory(input);
  if (names->GetSeriesUIDs().empty())
  {
    throw std::runtime_error("no DICOM series in " + input);
  }
  auto reader = itk::ImageSeriesReader<CTType>::New();
  reader->SetImageIO(itk::GDCMImageIO::New());
  reader->SetFileNames(names->GetFileNames(names->GetSeriesUIDs().front()));
  reader->Update();
  return reader->GetOutput();
}

/** Labels from HU, as a segmentation would give them: 0 air (<= -800 HU), 1 soft tissue, 2 bone (> 350 HU). */
DRRType::LabelImageType::Pointer
ThresholdLabels(const CTType * ct)
{
  auto labels = DRRType::LabelImageType::New();
  labels->CopyInformation(ct);
  labels->SetRegions(ct->GetLargestPossibleRegion());
  labels->Allocate();
  const size_t n = ct->GetBufferedRegion().GetNumberOfPixels();
  for (size_t v = 0; v < n; ++v)
  {
    const short hu = ct->GetBufferPointer()[v];
    labels->GetBufferPointer()[v] = hu <= -800 ? 0 : (hu <= 350 ? 1 : 2);
  }
  return labels;
}

/** -ln T of a kVp tube through the material channels of drr (rendered with a Materials transfer function), with
 * quantum noise of photons per pixel. */
ProjectionType::Pointer
Polychromatic(DRRType * drr, double kVp, double photons, uint64_t seed)
{
  auto spectrum = itk::DRRXRaySpectrum::New();
  spectrum->SetKramers(kVp); // 2.5 mm Al
  auto poly = itk::DRRPolychromaticImageFilter<DRRType::ChannelImageType, ProjectionType>::New();
  poly->SetInput(drr->GetChannelOutput());
  poly->SetCovarianceInput(drr->GetChannelCovarianceOutput());
  poly->SetMaterialTable(drr->GetTransferFunction()->GetMaterialTable());
  poly->SetReferenceEnergyInKeV(drr->GetTransferFunction()->GetEffectiveEnergyInKeV());
  poly->SetSpectrum(spectrum);
  auto noise = itk::DRRQuantumNoiseImageFilter<ProjectionType>::New();
  noise->SetInput(poly->GetOutput());
  noise->SetNumberOfPhotons(photons);
  noise->SetSeed(seed);
  noise->Update();
  return noise->GetOutput();
}
} // namespace

int
main(int argc, char * argv[])
{
  if (argc != 3 && argc != 4)
  {
    std::cerr << "usage: " << argv[0] << " CT_VOLUME_OR_DICOM_DIRECTORY OUTPUT_PREFIX [SAMPLES]\n";
    return EXIT_FAILURE;
  }
  try
  {
    const std::string prefix = argv[2];
    const auto        ct = ReadCT(argv[1]);
    auto              drr = DRRType::New();
    drr->SetInput(ct);
    drr->GetGeometry()->SetGantryAngleInDegrees(90.0); // AP
    drr->GetGeometry()->SetIsocenterToImageCenter(ct);
    drr->GetGeometry()->SetDetectorSize({ { 256, 256 } });
    drr->GetGeometry()->SetDetectorSpacing(itk::Vector<double, 2>(2.4)); // mm
    drr->SetNumberOfSamples(argc == 4 ? std::stoull(argv[3]) : 20000000);
    drr->SetSeed(1);
    drr->Update();
    itk::WriteImage(drr->GetOutput(), prefix + "_line_integral.mha");

    // Bone only: the voxels of label 2 attenuate, the others are air.
    const auto labels = ThresholdLabels(ct);
    itk::WriteImage(labels, prefix + "_labels.mha", true);
    drr->SetLabelImage(labels);
    drr->SetKeptLabels({ 2 });
    drr->Update();
    itk::WriteImage(drr->GetOutput(), prefix + "_bone.mha");

    // A polychromatic beam: mu at 60 keV per material (DeepDRR's air, soft tissue, bone), one channel each.
    drr->SetKeptLabels({});
    drr->SetLabelImage(nullptr);
    auto materials = itk::DRRMaterialTable::New();
    materials->SetDefault();
    drr->GetTransferFunction()->SetMaterialTable(materials);
    drr->SetMaterialChannels(true);
    drr->Update();
    itk::WriteImage(Polychromatic(drr, 70.0, 1e4, 2), prefix + "_70kvp.mha");
    itk::WriteImage(Polychromatic(drr, 120.0, 1e4, 3), prefix + "_120kvp.mha");
  }
  catch (const std::exception & e)
  {
    std::cerr << "error: " << e.what() << std::endl;
    return EXIT_FAILURE;
  }
  return EXIT_SUCCESS;
}
