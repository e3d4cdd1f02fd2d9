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

#include "itkDRRProjectionGeometryFileIO.h"
#include "itkDRRProjectionMatrixFileIO.h"
#include "itkEuler3DTransform.h"
#include "itkExactDRRImageFilter.h"
#include "itkImageFileReader.h"
#include "itkPointBasedDRRImageFilter.h"
#include "itkPowellOptimizer.h"
#include "itkSingleValuedCostFunction.h"
#include "gdcmReader.h"

#include <algorithm>
#include <chrono>
#include <cmath>
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
using EulerType = itk::Euler3DTransform<double>;
constexpr double degree = 3.14159265358979323846 / 180.0;

/** A copy of a view, bit for bit (through the geometry file format, which round-trips every field). */
GeometryType::Pointer
CopyGeometry(const GeometryType * geometry)
{
  std::stringstream text;
  itk::DRRProjectionGeometryFileIO::WriteToStream(text, geometry);
  auto copy = GeometryType::New();
  itk::DRRProjectionGeometryFileIO::ReadFromStream(text, copy);
  return copy;
}

/** The view binned shrink x shrink: coarse pixel K covers the fine pixels shrink K .. shrink K + shrink - 1 (a last
 * partial block is left out), so its centre is their mean. */
GeometryType::Pointer
BinnedGeometry(const GeometryType * geometry, unsigned shrink)
{
  auto binned = CopyGeometry(geometry);
  if (shrink == 1)
  {
    return binned;
  }
  GeometryType::DetectorSizeType   size;
  GeometryType::DetectorVectorType spacing, offset;
  for (unsigned d = 0; d < 2; ++d)
  {
    const double fine = static_cast<double>(geometry->GetDetectorSize()[d]);
    size[d] = std::max<itk::SizeValueType>(1, geometry->GetDetectorSize()[d] / shrink);
    const double coarse = static_cast<double>(size[d]);
    spacing[d] = geometry->GetDetectorSpacing()[d] * shrink;
    offset[d] =
      geometry->GetDetectorOffset()[d] +
      (0.5 * (shrink - 1.0) - 0.5 * (fine - 1.0) + 0.5 * (coarse - 1.0) * shrink) * geometry->GetDetectorSpacing()[d];
  }
  binned->SetDetectorSize(size);
  binned->SetDetectorSpacing(spacing);
  binned->SetDetectorOffset(offset);
  return binned;
}

/** The image binned as BinnedGeometry() bins its view: block means. */
std::vector<float>
BinnedImage(const ProjectionType * image, unsigned shrink)
{
  const auto         size = image->GetLargestPossibleRegion().GetSize();
  const size_t       columns = std::max<size_t>(1, size[0] / shrink), rows = std::max<size_t>(1, size[1] / shrink);
  const unsigned     block = std::min<size_t>(shrink, std::min(size[0], size[1]));
  std::vector<float> binned(columns * rows, 0.0f);
  const float *      in = image->GetBufferPointer();
  for (size_t r = 0; r < rows; ++r)
  {
    for (size_t c = 0; c < columns; ++c)
    {
      double sum = 0.0;
      for (unsigned j = 0; j < block; ++j)
      {
        for (unsigned i = 0; i < block; ++i)
        {
          sum += in[(r * shrink + j) * size[0] + c * shrink + i];
        }
      }
      binned[r * columns + c] = static_cast<float>(sum / (block * block));
    }
  }
  return binned;
}

/** The pixels whose rays cross the CT's grid [-0.5, n - 0.5]^3 at the pose: the field DRR and X-ray both cover. */
std::vector<uint8_t>
CoveredField(const GeometryType * geometry, const itk::ImageBase<3> * volume, const EulerType * pose)
{
  const auto           size = geometry->GetDetectorSize();
  const auto           extent = volume->GetLargestPossibleRegion().GetSize();
  const auto           inverse = pose->GetInverseTransform();
  std::vector<uint8_t> mask(size[0] * size[1], 0);
  const bool           parallel = geometry->GetProjection() == itk::PointBasedDRREnums::Projection::Parallel;
  const auto           toIndex = [&](const GeometryType::PointType & room) {
    // The overload that returns the index: ITK 6 marks the one that returns whether it is inside [[nodiscard]].
    return volume->TransformPhysicalPointToContinuousIndex<double>(inverse->TransformPoint(room));
  };
  for (unsigned row = 0; row < size[1]; ++row)
  {
    for (unsigned column = 0; column < size[0]; ++column)
    {
      const auto start = geometry->GetRayStart(column, row);
      auto       end = geometry->GetPixelCenter(column, row);
      if (parallel)
      {
        end = end + (end - start); // the whole line: as far beyond the detector as the start is before it
      }
      const auto a = toIndex(start), b = toIndex(end);
      double     enter = 0.0, exit = 1.0;
      for (unsigned k = 0; k < 3 && enter <= exit; ++k)
      {
        const double low = -0.5, high = static_cast<double>(extent[k]) - 0.5, d = b[k] - a[k];
        if (std::abs(d) < 1e-300)
        {
          exit = (a[k] < low || a[k] > high) ? -1.0 : exit;
          continue;
        }
        const double t1 = (low - a[k]) / d, t2 = (high - a[k]) / d;
        enter = std::max(enter, std::min(t1, t2));
        exit = std::min(exit, std::max(t1, t2));
      }
      mask[row * size[0] + column] = enter < exit ? 1 : 0;
    }
  }
  return mask;
}

/** The metric of a DRR and an X-ray (columns wide) over the mask: gradient correlation, or else NCC. */
double
Similarity(bool gradient, const float * drr, const float * xray, const std::vector<uint8_t> & mask, size_t columns)
{
  return gradient ? MaskedGradientCorrelation(drr, xray, mask, columns) : MaskedNormalizedCorrelation(drr, xray, mask);
}

/** Thrown by the cost when --max-seconds has passed: the best pose so far is the answer. */
struct TimeIsUp
{};

/** 1 - mean NCC of the X-rays and the DRRs at a pose (Euler3D parameters), on one level of the schedule, for a CT of
 * type TVolume. */
template <typename TVolume>
class SimilarityCost : public itk::SingleValuedCostFunction
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(SimilarityCost);
  using Self = SimilarityCost;
  using Superclass = itk::SingleValuedCostFunction;
  using Pointer = itk::SmartPointer<Self>;
  itkNewMacro(Self);

  /** One X-ray on this level: its binned view and pixels, and the filter that renders it. */
  struct Level
  {
    GeometryType::Pointer                                                    Geometry;
    std::vector<float>                                                       XRay;
    typename itk::PointBasedDRRImageFilter<TVolume, ProjectionType>::Pointer Points;
    typename itk::ExactDRRImageFilter<TVolume, ProjectionType>::Pointer      Exact;
  };

  std::vector<Level>                    Levels;
  bool                                  Gradient{ false }; // gradient correlation, else NCC
  const TVolume *                       Volume{ nullptr };
  EulerType::Pointer                    Pose;
  std::chrono::steady_clock::time_point Deadline{ std::chrono::steady_clock::time_point::max() };
  mutable unsigned                      Evaluations{ 0 };
  mutable double                        BestValue{ std::numeric_limits<double>::infinity() };
  mutable ParametersType                BestParameters;

  MeasureType
  GetValue(const ParametersType & parameters) const override
  {
    if (std::chrono::steady_clock::now() > Deadline)
    {
      throw TimeIsUp{};
    }
    ++Evaluations;
    Pose->SetParameters(parameters);
    double similarity = 0.0;
    for (const Level & level : Levels)
    {
      const ProjectionType * drr = Render(level, Pose);
      similarity += Similarity(Gradient,
                               drr->GetBufferPointer(),
                               level.XRay.data(),
                               CoveredField(level.Geometry, Volume, Pose),
                               level.Geometry->GetDetectorSize()[0]);
    }
    const double value = 1.0 - similarity / static_cast<double>(Levels.size());
    if (value < BestValue)
    {
      BestValue = value;
      BestParameters = parameters;
    }
    return value;
  }

  /** Renders level's view at the pose. */
  static const ProjectionType *
  Render(const Level & level, const EulerType * pose)
  {
    const auto roomToVolume = pose->GetInverseTransform();
    if (level.Exact)
    {
      level.Exact->SetTransform(roomToVolume);
      level.Exact->SetGeometry(level.Geometry);
      level.Exact->Update();
      return level.Exact->GetOutput();
    }
    level.Points->SetTransform(roomToVolume);
    level.Points->SetGeometry(level.Geometry);
    level.Points->Update();
    return level.Points->GetOutput();
  }

  void
  GetDerivative(const ParametersType &, DerivativeType &) const override
  {
    itkExceptionMacro("no derivative: a derivative-free optimizer is used");
  }

  unsigned
  GetNumberOfParameters() const override
  {
    return 6;
  }

protected:
  SimilarityCost() = default;
  ~SimilarityCost() override = default;
};

EulerType::ParametersType
ToParameters(const std::array<double, 6> & pose)
{
  EulerType::ParametersType parameters(6);
  for (unsigned k = 0; k < 3; ++k)
  {
    parameters[k] = pose[k + 3] * degree;
    parameters[k + 3] = pose[k];
  }
  return parameters;
}

std::array<double, 6>
ToPose(const EulerType::ParametersType & parameters)
{
  std::array<double, 6> pose{};
  for (unsigned k = 0; k < 3; ++k)
  {
    pose[k] = parameters[k + 3];
    pose[k + 3] = parameters[k] / degree;
  }
  return pose;
}
} // namespace

itk::Euler3DTransform<double>::Pointer
MakePoseTransform(const itk::ImageBase<3> * volume, const std::array<double, 6> & pose)
{
  auto transform = EulerType::New();
  transform->SetCenter(GeometryType::ComputeImageCenter(volume));
  transform->SetParameters(ToParameters(pose));
  return transform;
}

double
MaskedNormalizedCorrelation(const float * a, const float * b, const std::vector<uint8_t> & mask)
{
  double sa = 0.0, sb = 0.0, n = 0.0;
  for (size_t p = 0; p < mask.size(); ++p)
  {
    if (mask[p])
    {
      sa += a[p];
      sb += b[p];
      n += 1.0;
    }
  }
  if (n < 2.0)
  {
    return 0.0;
  }
  const double ma = sa / n, mb = sb / n;
  double       ab = 0.0, aa = 0.0, bb = 0.0;
  for (size_t p = 0; p < mask.size(); ++p)
  {
    if (mask[p])
    {
      ab += (a[p] - ma) * (b[p] - mb);
      aa += (a[p] - ma) * (a[p] - ma);
      bb += (b[p] - mb) * (b[p] - mb);
    }
  }
  return aa > 0.0 && bb > 0.0 ? ab / std::sqrt(aa * bb) : 0.0;
}

double
MaskedGradientCorrelation(const float * a, const float * b, const std::vector<uint8_t> & mask, size_t columns)
{
  const size_t rows = mask.size() / columns;
  double       sum = 0.0;
  for (const bool alongColumns : { true, false })
  {
    const size_t         step = alongColumns ? 1 : columns;
    std::vector<float>   da(mask.size(), 0.0f), db(mask.size(), 0.0f);
    std::vector<uint8_t> inside(mask.size(), 0);
    for (size_t r = alongColumns ? 0 : 1; r + (alongColumns ? 0 : 1) < rows; ++r)
    {
      for (size_t c = alongColumns ? 1 : 0; c + (alongColumns ? 1 : 0) < columns; ++c)
      {
        const size_t p = r * columns + c;
        inside[p] = mask[p - step] & mask[p + step];
        da[p] = a[p + step] - a[p - step];
        db[p] = b[p + step] - b[p - step];
      }
    }
    sum += MaskedNormalizedCorrelation(da.data(), db.data(), inside);
  }
  return 0.5 * sum;
}

const std::vector<std::string> &
RegistrationMetricNames()
{
  static const std::vector<std::string> names{ "ncc", "gc" };
  return names;
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
  if (xrays.empty())
  {
    throw std::runtime_error("registration needs at least one X-ray (--xray)");
  }
  const auto & metrics = RegistrationMetricNames();
  if (std::find(metrics.begin(), metrics.end(), settings.Metric) == metrics.end())
  {
    throw std::runtime_error("unknown registration metric '" + settings.Metric + "' (ncc or gc)");
  }
  for (const XRay & xray : xrays)
  {
    // The CT may move by the start pose and the search's reach (a few cm) towards the detector.
    CheckDetectorBeyondVolume(xray.Geometry, volume, 50.0, "the X-ray " + xray.Description);
  }
  const auto begin = std::chrono::steady_clock::now();
  auto       pose = MakePoseTransform(volume, settings.StartPose);

  // One filter per X-ray for the whole schedule: kept points are drawn once and re-projected at every pose and level.
  using CostType = SimilarityCost<TVolume>;
  std::vector<typename CostType::Level> filters(xrays.size());
  for (size_t x = 0; x < xrays.size(); ++x)
  {
    if (settings.Exact)
    {
      filters[x].Exact = itk::ExactDRRImageFilter<TVolume, ProjectionType>::New();
      filters[x].Exact->SetInput(volume);
      filters[x].Exact->SetRaysPerPixelSide(settings.ExactRaysPerSide);
    }
    else
    {
      auto points = itk::PointBasedDRRImageFilter<TVolume, ProjectionType>::New();
      points->SetInput(volume);
      points->SetNumberOfSamples(settings.Samples);
      points->SetSeed(settings.Seed + x);
      points->SetSplat(itk::PointBasedDRREnums::Splat::Bilinear); // a cost continuous in the pose
      points->SetReusePoints(true);
      filters[x].Points = points;
    }
  }

  RegistrationResult result;
  const auto         levelCost = [&](unsigned shrink) {
    auto cost = CostType::New();
    cost->Gradient = settings.Metric == "gc";
    cost->Volume = volume;
    cost->Pose = pose;
    if (settings.MaxSeconds > 0.0)
    {
      cost->Deadline = begin + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                 std::chrono::duration<double>(settings.MaxSeconds));
    }
    for (size_t x = 0; x < xrays.size(); ++x)
    {
      typename CostType::Level level = filters[x];
      level.Geometry = BinnedGeometry(xrays[x].Geometry, shrink);
      level.XRay = BinnedImage(xrays[x].Image, shrink);
      cost->Levels.push_back(level);
    }
    return cost;
  };
  const unsigned firstShrink = settings.Shrink.empty() ? 1 : settings.Shrink.front();
  result.StartSimilarity = 1.0 - levelCost(firstShrink)->GetValue(pose->GetParameters());

  auto parameters = pose->GetParameters();
  for (const unsigned shrink : settings.Shrink)
  {
    auto cost = levelCost(shrink);
    auto optimizer = itk::PowellOptimizer::New();
    optimizer->SetCostFunction(cost);
    optimizer->SetInitialPosition(parameters);
    itk::PowellOptimizer::ScalesType scales(6);
    for (unsigned k = 0; k < 6; ++k)
    {
      scales[k] = k < 3 ? 1.0 / degree : 1.0; // one optimizer unit: one degree or one millimetre
    }
    optimizer->SetScales(scales);
    optimizer->SetMaximize(false);
    optimizer->SetStepLength(std::max(1.0, static_cast<double>(shrink)));
    optimizer->SetStepTolerance(0.02 * shrink);
    optimizer->SetValueTolerance(1e-7);
    optimizer->SetMaximumIteration(8);
    optimizer->SetMaximumLineIteration(12);
    try
    {
      optimizer->StartOptimization();
      parameters = optimizer->GetCurrentPosition();
      if (cost->BestValue < cost->GetValue(parameters))
      {
        parameters = cost->BestParameters;
      }
    }
    catch (const TimeIsUp &)
    {
      result.StoppedByTime = true;
      if (cost->BestParameters.size() == 6)
      {
        parameters = cost->BestParameters;
      }
    }
    result.Evaluations += cost->Evaluations;
    if (settings.Verbose)
    {
      const auto level = ToPose(parameters);
      std::cerr << "pbdrr: register: level 1/" << shrink << ": " << settings.Metric << " " << 1.0 - cost->BestValue
                << " after " << cost->Evaluations << " DRRs, pose " << level[0] << " " << level[1] << " " << level[2]
                << " " << level[3] << " " << level[4] << " " << level[5] << std::endl;
    }
    if (result.StoppedByTime)
    {
      break;
    }
  }
  pose->SetParameters(parameters);
  result.Pose = ToPose(parameters);
  // The final DRRs and similarity, at full resolution.
  double similarity = 0.0;
  for (size_t x = 0; x < xrays.size(); ++x)
  {
    typename CostType::Level level = filters[x];
    level.Geometry = CopyGeometry(xrays[x].Geometry);
    const ProjectionType * drr = CostType::Render(level, pose);
    auto                   kept = ProjectionType::New();
    kept->CopyInformation(drr);
    kept->SetRegions(drr->GetLargestPossibleRegion());
    kept->Allocate();
    std::copy(drr->GetBufferPointer(),
              drr->GetBufferPointer() + drr->GetLargestPossibleRegion().GetNumberOfPixels(),
              kept->GetBufferPointer());
    result.Masks.push_back(CoveredField(level.Geometry, volume, pose));
    similarity += Similarity(settings.Metric == "gc",
                             kept->GetBufferPointer(),
                             xrays[x].Image->GetBufferPointer(),
                             result.Masks.back(),
                             level.Geometry->GetDetectorSize()[0]);
    result.FinalDRRs.push_back(kept);
  }
  result.Similarity = similarity / static_cast<double>(xrays.size());
  result.Seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  return result;
}

template RegistrationResult
RegisterToXRays(const HUVolumeType *, const std::vector<XRay> &, const RegistrationSettings &);
template RegistrationResult
RegisterToXRays(const VolumeType *, const std::vector<XRay> &, const RegistrationSettings &);
} // namespace pbdrr
