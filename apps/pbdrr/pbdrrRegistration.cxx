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
#include "pbdrrRegistration.h"
#include "pbdrrDicomLocalizerGeometry.h"
#include "pbdrrView.h"
#include "pbdrrVolumeFileReader.h"

#include "itkDRRImageSimilarity.h"
#include "itkDRRProjectionMatrixFileIO.h"
#include "itkImageFileReader.h"
#include "itkPointBasedDRRRegistrationMethod.h"
#include "gdcmReader.h"

#include <algorithm>
#include <iostream>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace pbdrr
{
namespace
{
using ProjectionType = itk::Image<float, 2>;
using GeometryType = itk::DRRProjectionGeometry;
} // namespace

itk::Euler3DTransform<double>::Pointer
MakePoseTransform(const itk::ImageBase<3> * volume, const std::array<double, 6> & pose)
{
  itk::FixedArray<double, 6> fixed;
  std::copy(pose.begin(), pose.end(), fixed.Begin());
  return itk::PointBasedDRRRegistrationMethod<VolumeType>::MakePoseTransform(volume, fixed);
}

itk::DRRProjectionGeometry::Pointer
XRayViewOfFile(const std::string & geometryFile, const itk::ImageBase<3> * volume)
{
  Options options;
  options.geometryFile = geometryFile;
  return MakeGeometry(options, volume);
}

XRay
ReadXRay(const std::string &       image,
         const std::string &       geometryFile,
         const std::string &       matrixFile,
         const itk::ImageBase<3> * volume)
{
  if (!geometryFile.empty() && !matrixFile.empty())
  {
    throw std::runtime_error(image + ": give its view by --geometry or by --projection-matrix, not both");
  }
  XRay xray;
  RefuseDamagedImageFile(image);
  xray.Image = itk::ReadImage<ProjectionType>(image);
  const auto size = xray.Image->GetLargestPossibleRegion().GetSize();
  if (!geometryFile.empty())
  {
    xray.Geometry = XRayViewOfFile(geometryFile, volume);
    xray.Description = image + " in the view of " + geometryFile;
  }
  else if (!matrixFile.empty())
  {
    auto reader = itk::DRRProjectionMatrixFileIO::New();
    reader->SetFileName(matrixFile);
    xray.Geometry = GeometryType::New();
    // The image's pixel spacing is the detector's pitch: it places the detector SID = fx du from the source.
    GeometryType::DetectorVectorType pitch;
    pitch[0] = xray.Image->GetSpacing()[0];
    pitch[1] = xray.Image->GetSpacing()[1];
    xray.Geometry->SetDetectorSpacing(pitch);
    xray.Geometry->SetProjectionMatrix(reader->Read(), { { size[0], size[1] } });
    xray.Description = image + " in the view of the projection matrix " + matrixFile;
  }
  else
  {
    const LocalizerView view = ReadLocalizerView(image);
    xray.Geometry = view.Geometry;
    xray.Description = image + ": " + view.Description;
  }
  xray.Geometry->VerifyGeometry();
  if (xray.Geometry->GetDetectorSize()[0] != size[0] || xray.Geometry->GetDetectorSize()[1] != size[1])
  {
    std::ostringstream message;
    message << image << " is " << size[0] << " x " << size[1] << " pixels, its view "
            << xray.Geometry->GetDetectorSize()[0] << " x " << xray.Geometry->GetDetectorSize()[1];
    throw std::runtime_error(message.str());
  }
  // MONOCHROME1 shows attenuation dark: invert, so that the X-ray and the DRR agree in sign (NCC is blind to the rest).
  gdcm::Reader reader;
  reader.SetFileName(image.c_str());
  if (reader.ReadUpToTag(gdcm::Tag(0x7fe0, 0x0010)))
  {
    const gdcm::DataSet & dataSet = reader.GetFile().GetDataSet();
    const gdcm::Tag       photometric(0x0028, 0x0004);
    if (dataSet.FindDataElement(photometric) && dataSet.GetDataElement(photometric).GetByteValue())
    {
      const auto * bytes = dataSet.GetDataElement(photometric).GetByteValue();
      if (std::string(bytes->GetPointer(), bytes->GetLength()).find("MONOCHROME1") != std::string::npos)
      {
        float * pixels = xray.Image->GetBufferPointer();
        for (size_t p = 0; p < xray.Image->GetBufferedRegion().GetNumberOfPixels(); ++p)
        {
          pixels[p] = -pixels[p];
        }
        xray.Description += " (MONOCHROME1: inverted)";
      }
    }
  }
  return xray;
}

void
CheckDetectorBeyondVolume(const GeometryType *      geometry,
                          const itk::ImageBase<3> * volume,
                          double                    marginInMillimeters,
                          const std::string &       flag)
{
  if (geometry->GetProjection() != itk::PointBasedDRREnums::Projection::Perspective)
  {
    return;
  }
  const auto size = volume->GetLargestPossibleRegion().GetSize();
  const auto source = geometry->GetSourcePosition();
  const auto n = geometry->GetNormal();
  double     farthest = -std::numeric_limits<double>::infinity();
  for (unsigned corner = 0; corner < 8; ++corner)
  {
    itk::ContinuousIndex<double, 3> index;
    for (unsigned a = 0; a < 3; ++a)
    {
      index[a] = (corner >> a) & 1u ? static_cast<double>(size[a]) - 0.5 : -0.5;
    }
    itk::Point<double, 3> point;
    volume->TransformContinuousIndexToPhysicalPoint(index, point);
    farthest = std::max(farthest, (source - point) * n);
  }
  farthest += marginInMillimeters;
  const double sid = geometry->GetSourceToDetectorDistance();
  if (farthest > sid)
  {
    const double       focal = sid / geometry->GetDetectorSpacing()[0];
    std::ostringstream message;
    message << "the detector of " << flag << " lies " << sid << " mm from the source (focal length " << focal
            << " pixels x column pitch " << geometry->GetDetectorSpacing()[0] << " mm), inside the CT, which reaches "
            << farthest << " mm from it: the rays end at the detector. Give the detector's pixel pitch, at least "
            << farthest / focal << " mm here";
    throw std::runtime_error(message.str());
  }
}

template <typename TVolume>
RegistrationResult
RegisterToXRays(const TVolume * volume, const std::vector<XRay> & xrays, const RegistrationSettings & settings)
{
  for (const XRay & xray : xrays)
  {
    // The CT may move by the start pose and the search's reach (a few cm) towards the detector.
    CheckDetectorBeyondVolume(xray.Geometry, volume, 50.0, "the X-ray " + xray.Description);
  }
  using MethodType = itk::PointBasedDRRRegistrationMethod<TVolume>;
  auto method = MethodType::New();
  method->SetVolume(volume);
  for (const XRay & xray : xrays)
  {
    method->AddXRay(xray.Image, xray.Geometry);
  }
  typename MethodType::PoseType start;
  std::copy(settings.StartPose.begin(), settings.StartPose.end(), start.Begin());
  method->SetStartPose(start);
  // A schedule given replaces the default one, per-level points and smoothing included (none given: --samples on
  // every level, no smoothing); --samples alone sets every default level's points.
  if (!settings.Shrink.empty())
  {
    method->SetShrinkFactorsPerLevel(settings.Shrink);
    method->SetNumberOfSamplesPerLevel(settings.LevelSamples);
    method->SetSmoothingSigmasPerLevel(settings.LevelSigmas);
  }
  else if (settings.Samples > 0)
  {
    method->SetNumberOfSamplesPerLevel(
      typename MethodType::SamplesArrayType(method->GetShrinkFactorsPerLevel().size(), settings.Samples));
  }
  method->SetNumberOfStarts(settings.Starts);
  method->SetStartRadius(settings.StartRadius);
  method->SetMaximumTimeInSeconds(settings.MaxSeconds);
  if (!settings.Optimizer.empty())
  {
    method->SetOptimizer(MethodType::MakeOptimizer(settings.Optimizer));
  }
  auto * metric = method->GetModifiableMetric();
  metric->SetSimilarity(itk::DRRImageSimilarity::FromName(settings.Metric));
  metric->SetExactRaysPerPixelSide(settings.Exact ? settings.ExactRaysPerSide : 0);
  if (settings.Samples > 0)
  {
    metric->SetNumberOfSamples(settings.Samples);
  }
  metric->SetSeed(settings.Seed);
  if (settings.Threads > 0)
  {
    method->SetNumberOfWorkUnits(settings.Threads);
  }
  if (settings.Verbose)
  {
    const MethodType * observed = method;
    method->AddObserver(itk::IterationEvent(), [observed, &settings](const itk::EventObject &) {
      const auto pose = observed->GetCurrentPose();
      std::cerr << "pbdrr: register: level " << observed->GetCurrentLevel() + 1 << " (1/"
                << observed->GetCurrentShrinkFactor() << "): " << settings.Metric << " "
                << observed->GetCurrentLevelSimilarity() << " after " << observed->GetCurrentLevelEvaluations()
                << " DRRs, pose " << pose[0] << " " << pose[1] << " " << pose[2] << " " << pose[3] << " " << pose[4]
                << " " << pose[5] << "; " << observed->GetCurrentStopCondition() << std::endl;
    });
  }
  method->Update();

  RegistrationResult                  result;
  const typename MethodType::PoseType pose = method->GetPose();
  std::copy(pose.Begin(), pose.End(), result.Pose.begin());
  result.StartSimilarity = method->GetStartSimilarity();
  result.Similarity = method->GetSimilarity();
  result.Evaluations = static_cast<unsigned>(method->GetNumberOfEvaluations());
  result.DerivativeEvaluations = static_cast<unsigned>(method->GetNumberOfDerivativeEvaluations());
  result.Seconds = method->GetElapsedSeconds();
  result.StoppedByTime = method->GetStoppedByTimeLimit();
  for (unsigned x = 0; x < method->GetNumberOfXRays(); ++x)
  {
    result.FinalDRRs.emplace_back(method->GetFinalDRR(x));
    result.Masks.emplace_back(method->GetFinalMask(x));
  }
  return result;
}

template RegistrationResult
RegisterToXRays(const HUVolumeType *, const std::vector<XRay> &, const RegistrationSettings &);
template RegistrationResult
RegisterToXRays(const VolumeType *, const std::vector<XRay> &, const RegistrationSettings &);
} // namespace pbdrr
