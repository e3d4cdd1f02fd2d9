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
#ifndef itkPointBasedDRRRegistrationMethod_hxx
#define itkPointBasedDRRRegistrationMethod_hxx

#include "itkDRRImageSimilarity.h"
#include "itkDRRImageToAttenuationVolumeFilter.h"
#include "itkDRRProjectionGeometryFileIO.h"
#include "itkExactDRRImageFilter.h"
#include "itkPointBasedDRRImageFilter.h"
#include "itkPowellOptimizer.h"
#include "itkSingleValuedCostFunction.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

namespace itk
{
/** 1 - the mean similarity of the X-rays and the DRRs at a pose (Euler3DTransform's parameters), on one level of the
 * schedule. */
template <typename TInputImage>
class PointBasedDRRRegistrationMethod<TInputImage>::LevelCost : public SingleValuedCostFunction
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(LevelCost);
  using Self = LevelCost;
  using Superclass = SingleValuedCostFunction;
  using Pointer = SmartPointer<Self>;
  /** Method for creation through the object factory. */
  itkNewMacro(Self);
  using typename Superclass::DerivativeType;
  using typename Superclass::MeasureType;
  using typename Superclass::ParametersType;

  /** One X-ray on this level: its binned view and pixels, and the filter that renders it. */
  struct Level
  {
    /** The view, binned. */
    GeometryType::Pointer Geometry;
    /** The X-ray's pixels, binned alike. */
    std::vector<float> XRay;
    /** The kept points' filter (or null). */
    typename PointBasedDRRImageFilter<TInputImage, XRayImageType>::Pointer Points;
    /** The exact projector (or null). */
    typename ExactDRRImageFilter<TInputImage, XRayImageType>::Pointer Exact;
  };

  /** One per X-ray. */
  std::vector<Level> Levels;
  /** The similarity's name. */
  std::string Metric;
  /** The CT. */
  const TInputImage * Volume{ nullptr };
  /** The pose evaluated (set to the parameters). */
  TransformType::Pointer Pose;
  /** Past it, GetValue() throws TimeIsUp. */
  std::chrono::steady_clock::time_point Deadline{ std::chrono::steady_clock::time_point::max() };
  /** The poses evaluated. */
  mutable SizeValueType Evaluations{ 0 };
  /** The lowest cost so far. */
  mutable double BestValue{ std::numeric_limits<double>::infinity() };
  /** Where it was found. */
  mutable ParametersType BestParameters;

  /** 1 - the mean similarity at parameters; throws TimeIsUp past the deadline. */
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
      const XRayImageType * drr = Render(level, Pose);
      similarity += DRRImageSimilarity::Evaluate(Metric,
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
  static const XRayImageType *
  Render(const Level & level, const TransformType * pose)
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

  /** Throws: Powell's method needs none. */
  void
  GetDerivative(const ParametersType &, DerivativeType &) const override
  {
    itkExceptionMacro("no derivative: a derivative-free optimizer is used");
  }

  /** Six: Euler3DTransform's. */
  unsigned int
  GetNumberOfParameters() const override
  {
    return 6;
  }

protected:
  LevelCost() = default;
  ~LevelCost() override = default;
};

template <typename TInputImage>
PointBasedDRRRegistrationMethod<TInputImage>::PointBasedDRRRegistrationMethod()
{
  this->SetPrimaryInputName("Volume");
  this->SetNumberOfRequiredInputs(1);
  this->SetNumberOfRequiredOutputs(1);
  this->ProcessObject::SetNthOutput(0, this->MakeOutput(0));
}

template <typename TInputImage>
void
PointBasedDRRRegistrationMethod<TInputImage>::SetVolume(const InputImageType * volume)
{
  this->ProcessObject::SetNthInput(0, const_cast<InputImageType *>(volume));
}

template <typename TInputImage>
auto
PointBasedDRRRegistrationMethod<TInputImage>::GetVolume() const -> const InputImageType *
{
  return itkDynamicCastInDebugMode<const InputImageType *>(this->GetPrimaryInput());
}

template <typename TInputImage>
void
PointBasedDRRRegistrationMethod<TInputImage>::AddXRay(const XRayImageType * image, const GeometryType * geometry)
{
  const auto index = static_cast<DataObjectPointerArraySizeType>(m_XRayGeometries.size()) + 1;
  m_XRayGeometries.emplace_back(geometry);
  this->ProcessObject::SetNthInput(index, const_cast<XRayImageType *>(image));
  this->Modified();
}

template <typename TInputImage>
void
PointBasedDRRRegistrationMethod<TInputImage>::RemoveAllXRays()
{
  m_XRayGeometries.clear();
  this->SetNumberOfIndexedInputs(1);
  this->Modified();
}

template <typename TInputImage>
unsigned int
PointBasedDRRRegistrationMethod<TInputImage>::GetNumberOfXRays() const
{
  return static_cast<unsigned int>(m_XRayGeometries.size());
}

template <typename TInputImage>
auto
PointBasedDRRRegistrationMethod<TInputImage>::GetXRayImage(unsigned int index) const -> const XRayImageType *
{
  return index < m_XRayGeometries.size()
           ? itkDynamicCastInDebugMode<const XRayImageType *>(this->ProcessObject::GetInput(index + 1))
           : nullptr;
}

template <typename TInputImage>
auto
PointBasedDRRRegistrationMethod<TInputImage>::GetXRayGeometry(unsigned int index) const -> const GeometryType *
{
  return index < m_XRayGeometries.size() ? m_XRayGeometries[index].GetPointer() : nullptr;
}

template <typename TInputImage>
void
PointBasedDRRRegistrationMethod<TInputImage>::SetShrinkFactorsPerLevel(const ShrinkFactorsArrayType & factors)
{
  if (factors != m_ShrinkFactorsPerLevel)
  {
    m_ShrinkFactorsPerLevel = factors;
    this->Modified();
  }
}

template <typename TInputImage>
ProcessObject::DataObjectPointer
PointBasedDRRRegistrationMethod<TInputImage>::MakeOutput(DataObjectPointerArraySizeType)
{
  auto decorated = DecoratedTransformType::New();
  decorated->Set(TransformType::New());
  return decorated.GetPointer();
}

template <typename TInputImage>
auto
PointBasedDRRRegistrationMethod<TInputImage>::GetTransformOutput() const -> const DecoratedTransformType *
{
  return static_cast<const DecoratedTransformType *>(this->ProcessObject::GetOutput(0));
}

template <typename TInputImage>
auto
PointBasedDRRRegistrationMethod<TInputImage>::GetTransform() const -> const TransformType *
{
  return this->GetTransformOutput()->Get();
}

template <typename TInputImage>
auto
PointBasedDRRRegistrationMethod<TInputImage>::GetFinalDRR(unsigned int index) const -> const XRayImageType *
{
  return index < m_FinalDRRs.size() ? m_FinalDRRs[index].GetPointer() : nullptr;
}

template <typename TInputImage>
auto
PointBasedDRRRegistrationMethod<TInputImage>::GetFinalMask(unsigned int index) const -> const MaskImageType *
{
  return index < m_FinalMasks.size() ? m_FinalMasks[index].GetPointer() : nullptr;
}

template <typename TInputImage>
ModifiedTimeType
PointBasedDRRRegistrationMethod<TInputImage>::GetMTime() const
{
  ModifiedTimeType latest = Superclass::GetMTime();
  for (const auto & geometry : m_XRayGeometries)
  {
    latest = geometry ? std::max(latest, geometry->GetMTime()) : latest;
  }
  return m_TransferFunction ? std::max(latest, m_TransferFunction->GetMTime()) : latest;
}

template <typename TInputImage>
auto
PointBasedDRRRegistrationMethod<TInputImage>::ToParameters(const PoseType & pose) -> TransformType::ParametersType
{
  constexpr double              degree = 3.14159265358979323846 / 180.0;
  TransformType::ParametersType parameters(6);
  for (unsigned int k = 0; k < 3; ++k)
  {
    parameters[k] = pose[k + 3] * degree;
    parameters[k + 3] = pose[k];
  }
  return parameters;
}

template <typename TInputImage>
auto
PointBasedDRRRegistrationMethod<TInputImage>::ToPose(const TransformType::ParametersType & parameters) -> PoseType
{
  constexpr double degree = 3.14159265358979323846 / 180.0;
  PoseType         pose;
  for (unsigned int k = 0; k < 3; ++k)
  {
    pose[k] = parameters[k + 3];
    pose[k + 3] = parameters[k] / degree;
  }
  return pose;
}

template <typename TInputImage>
auto
PointBasedDRRRegistrationMethod<TInputImage>::MakePoseTransform(const ImageBase<3> * volume, const PoseType & pose)
  -> TransformType::Pointer
{
  auto transform = TransformType::New();
  transform->SetCenter(GeometryType::ComputeImageCenter(volume));
  transform->SetParameters(ToParameters(pose));
  return transform;
}

template <typename TInputImage>
auto
PointBasedDRRRegistrationMethod<TInputImage>::CopyGeometry(const GeometryType * geometry) -> GeometryType::Pointer
{
  // Through the geometry file format, which round-trips every field.
  std::stringstream text;
  DRRProjectionGeometryFileIO::WriteToStream(text, geometry);
  auto copy = GeometryType::New();
  DRRProjectionGeometryFileIO::ReadFromStream(text, copy);
  return copy;
}

template <typename TInputImage>
auto
PointBasedDRRRegistrationMethod<TInputImage>::BinnedGeometry(const GeometryType * geometry, unsigned int shrink)
  -> GeometryType::Pointer
{
  // Coarse pixel K covers the fine pixels shrink K .. shrink K + shrink - 1, so its centre is their mean.
  auto binned = CopyGeometry(geometry);
  if (shrink == 1)
  {
    return binned;
  }
  GeometryType::DetectorSizeType   size;
  GeometryType::DetectorVectorType spacing, offset;
  for (unsigned int d = 0; d < 2; ++d)
  {
    const double fine = static_cast<double>(geometry->GetDetectorSize()[d]);
    size[d] = std::max<SizeValueType>(1, geometry->GetDetectorSize()[d] / shrink);
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

template <typename TInputImage>
std::vector<float>
PointBasedDRRRegistrationMethod<TInputImage>::BinnedImage(const XRayImageType * image, unsigned int shrink)
{
  const auto         size = image->GetLargestPossibleRegion().GetSize();
  const size_t       columns = std::max<size_t>(1, size[0] / shrink), rows = std::max<size_t>(1, size[1] / shrink);
  const unsigned int block = std::min<size_t>(shrink, std::min(size[0], size[1]));
  std::vector<float> binned(columns * rows, 0.0f);
  const float *      in = image->GetBufferPointer();
  for (size_t r = 0; r < rows; ++r)
  {
    for (size_t c = 0; c < columns; ++c)
    {
      double sum = 0.0;
      for (unsigned int j = 0; j < block; ++j)
      {
        for (unsigned int i = 0; i < block; ++i)
        {
          sum += in[(r * shrink + j) * size[0] + c * shrink + i];
        }
      }
      binned[r * columns + c] = static_cast<float>(sum / (block * block));
    }
  }
  return binned;
}

template <typename TInputImage>
std::vector<uint8_t>
PointBasedDRRRegistrationMethod<TInputImage>::CoveredField(const GeometryType *  geometry,
                                                           const ImageBase<3> *  volume,
                                                           const TransformType * pose)
{
  // A slab test per pixel against the grid [-0.5, n - 0.5]^3, in the volume's continuous index.
  const auto           size = geometry->GetDetectorSize();
  const auto           extent = volume->GetLargestPossibleRegion().GetSize();
  const auto           inverse = pose->GetInverseTransform();
  std::vector<uint8_t> mask(size[0] * size[1], 0);
  const bool           parallel = geometry->GetProjection() == PointBasedDRREnums::Projection::Parallel;
  const auto           toIndex = [&](const GeometryType::PointType & room) {
    // The overload that returns the index: ITK 6 marks the one that returns whether it is inside [[nodiscard]].
    return volume->TransformPhysicalPointToContinuousIndex<double>(inverse->TransformPoint(room));
  };
  for (unsigned int row = 0; row < size[1]; ++row)
  {
    for (unsigned int column = 0; column < size[0]; ++column)
    {
      const auto start = geometry->GetRayStart(column, row);
      auto       end = geometry->GetPixelCenter(column, row);
      if (parallel)
      {
        end = end + (end - start); // the whole line: as far beyond the detector as the start is before it
      }
      const auto a = toIndex(start), b = toIndex(end);
      double     enter = 0.0, exit = 1.0;
      for (unsigned int k = 0; k < 3 && enter <= exit; ++k)
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

template <typename TInputImage>
void
PointBasedDRRRegistrationMethod<TInputImage>::VerifyPreconditions() const
{
  Superclass::VerifyPreconditions();
  if (m_XRayGeometries.empty())
  {
    itkExceptionMacro("registration needs at least one X-ray (AddXRay())");
  }
  for (unsigned int x = 0; x < m_XRayGeometries.size(); ++x)
  {
    if (!this->GetXRayImage(x) || !m_XRayGeometries[x])
    {
      itkExceptionMacro("X-ray " << x << " has no image or no geometry");
    }
  }
  if (m_ShrinkFactorsPerLevel.empty())
  {
    itkExceptionMacro("the schedule has no level: give at least one shrink factor");
  }
  for (const unsigned int shrink : m_ShrinkFactorsPerLevel)
  {
    if (shrink < 1)
    {
      itkExceptionMacro("a shrink factor is 0: each level bins the detector 1 x 1 or more");
    }
  }
  if (!DRRImageSimilarity::IsMetricName(m_Metric))
  {
    itkExceptionMacro("unknown registration metric '" << m_Metric << "' ("
                                                      << DRRImageSimilarity::JoinMetricNames(" or ") << ")");
  }
  if (!m_UseExactProjector && m_NumberOfSamples == 0)
  {
    itkExceptionMacro("the number of samples is 0: the kept points' DRRs need at least one point");
  }
  if (!(m_MaximumTimeInSeconds >= 0.0))
  {
    itkExceptionMacro("the time limit is " << m_MaximumTimeInSeconds << " s: give 0 (none) or a positive number");
  }
}

template <typename TInputImage>
void
PointBasedDRRRegistrationMethod<TInputImage>::VerifyInputInformation() const
{
  const auto extent = this->GetVolume()->GetLargestPossibleRegion().GetSize();
  if (extent[0] == 0 || extent[1] == 0 || extent[2] == 0)
  {
    itkExceptionMacro("the volume is empty (" << extent[0] << " x " << extent[1] << " x " << extent[2] << " voxels)");
  }
  for (unsigned int x = 0; x < m_XRayGeometries.size(); ++x)
  {
    m_XRayGeometries[x]->VerifyGeometry();
    const auto size = this->GetXRayImage(x)->GetLargestPossibleRegion().GetSize();
    const auto detector = m_XRayGeometries[x]->GetDetectorSize();
    if (detector[0] != size[0] || detector[1] != size[1])
    {
      itkExceptionMacro("X-ray " << x << " is " << size[0] << " x " << size[1] << " pixels, its view " << detector[0]
                                 << " x " << detector[1]);
    }
  }
}

template <typename TInputImage>
void
PointBasedDRRRegistrationMethod<TInputImage>::GenerateData()
{
  const InputImageType * volume = this->GetVolume();
  const size_t           count = m_XRayGeometries.size();
  const auto             begin = std::chrono::steady_clock::now();
  auto                   pose = MakePoseTransform(volume, m_StartPose);
  m_NumberOfEvaluations = 0;
  m_StoppedByTimeLimit = false;
  m_FinalDRRs.clear();
  m_FinalMasks.clear();

  // One filter per X-ray for the whole schedule: kept points are drawn once and re-projected at every pose and level.
  // The filters share one attenuation model, built once for all the X-rays.
  auto model = DRRImageToAttenuationVolumeFilter<InputImageType>::New();
  model->SetInput(volume);
  model->SetNumberOfWorkUnits(this->GetNumberOfWorkUnits());
  if (m_TransferFunction)
  {
    model->SetTransferFunction(m_TransferFunction);
  }
  using Level = typename LevelCost::Level;
  std::vector<Level> filters(count);
  for (size_t x = 0; x < count; ++x)
  {
    if (m_UseExactProjector)
    {
      auto exact = ExactDRRImageFilter<InputImageType, XRayImageType>::New();
      exact->SetAttenuationVolume(model->GetOutput());
      exact->SetRaysPerPixelSide(m_ExactRaysPerPixelSide);
      exact->SetReconstructionKernel(m_ReconstructionKernel);
      exact->SetNumberOfWorkUnits(this->GetNumberOfWorkUnits());
      filters[x].Exact = exact;
    }
    else
    {
      auto points = PointBasedDRRImageFilter<InputImageType, XRayImageType>::New();
      points->SetAttenuationVolume(model->GetOutput());
      points->SetNumberOfSamples(m_NumberOfSamples);
      points->SetSeed(m_Seed + x);
      points->SetReconstructionKernel(m_ReconstructionKernel);
      points->SetSplat(PointBasedDRREnums::Splat::Bilinear); // a cost continuous in the pose
      points->SetReusePoints(true);
      points->SetNumberOfWorkUnits(this->GetNumberOfWorkUnits());
      filters[x].Points = points;
    }
  }

  const auto levelCost = [&](unsigned int shrink) {
    auto cost = LevelCost::New();
    cost->Metric = m_Metric;
    cost->Volume = volume;
    cost->Pose = pose;
    if (m_MaximumTimeInSeconds > 0.0)
    {
      cost->Deadline = begin + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                 std::chrono::duration<double>(m_MaximumTimeInSeconds));
    }
    for (size_t x = 0; x < count; ++x)
    {
      Level level = filters[x];
      level.Geometry = BinnedGeometry(m_XRayGeometries[x], shrink);
      level.XRay = BinnedImage(this->GetXRayImage(x), shrink);
      cost->Levels.push_back(level);
    }
    return cost;
  };
  m_StartSimilarity = 1.0 - levelCost(m_ShrinkFactorsPerLevel.front())->GetValue(pose->GetParameters());

  auto parameters = pose->GetParameters();
  for (unsigned int levelIndex = 0; levelIndex < m_ShrinkFactorsPerLevel.size(); ++levelIndex)
  {
    const unsigned int shrink = m_ShrinkFactorsPerLevel[levelIndex];
    auto               cost = levelCost(shrink);
    auto               optimizer = PowellOptimizer::New();
    optimizer->SetCostFunction(cost);
    optimizer->SetInitialPosition(parameters);
    constexpr double            degree = 3.14159265358979323846 / 180.0;
    PowellOptimizer::ScalesType scales(6);
    for (unsigned int k = 0; k < 6; ++k)
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
      m_StoppedByTimeLimit = true;
      if (cost->BestParameters.size() == 6)
      {
        parameters = cost->BestParameters;
      }
    }
    m_NumberOfEvaluations += cost->Evaluations;
    m_CurrentLevel = levelIndex;
    m_CurrentShrinkFactor = shrink;
    m_CurrentLevelSimilarity = 1.0 - cost->BestValue;
    m_CurrentLevelEvaluations = cost->Evaluations;
    m_CurrentPose = ToPose(parameters);
    this->InvokeEvent(IterationEvent());
    this->UpdateProgress(static_cast<float>(levelIndex + 1) / static_cast<float>(m_ShrinkFactorsPerLevel.size()));
    if (m_StoppedByTimeLimit)
    {
      break;
    }
  }
  pose->SetParameters(parameters);
  m_Pose = ToPose(parameters);

  // The final DRRs and similarity, at full resolution.
  double similarity = 0.0;
  for (size_t x = 0; x < count; ++x)
  {
    Level level = filters[x];
    level.Geometry = CopyGeometry(m_XRayGeometries[x]);
    const XRayImageType * drr = LevelCost::Render(level, pose);
    auto                  kept = XRayImageType::New();
    kept->CopyInformation(drr);
    kept->SetRegions(drr->GetLargestPossibleRegion());
    kept->Allocate();
    std::copy(drr->GetBufferPointer(),
              drr->GetBufferPointer() + drr->GetLargestPossibleRegion().GetNumberOfPixels(),
              kept->GetBufferPointer());
    const std::vector<uint8_t> field = CoveredField(level.Geometry, volume, pose);
    similarity += DRRImageSimilarity::Evaluate(m_Metric,
                                               kept->GetBufferPointer(),
                                               this->GetXRayImage(x)->GetBufferPointer(),
                                               field,
                                               level.Geometry->GetDetectorSize()[0]);
    auto mask = MaskImageType::New();
    mask->CopyInformation(kept);
    mask->SetRegions(kept->GetLargestPossibleRegion());
    mask->Allocate();
    std::copy(field.begin(), field.end(), mask->GetBufferPointer());
    m_FinalDRRs.push_back(kept);
    m_FinalMasks.push_back(mask);
  }
  m_Similarity = similarity / static_cast<double>(count);
  auto * output = static_cast<DecoratedTransformType *>(this->ProcessObject::GetOutput(0));
  output->Set(pose);
  m_ElapsedSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
}

template <typename TInputImage>
void
PointBasedDRRRegistrationMethod<TInputImage>::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "NumberOfXRays: " << m_XRayGeometries.size() << std::endl;
  os << indent << "StartPose (mm, degrees): " << m_StartPose << std::endl;
  os << indent << "ShrinkFactorsPerLevel:";
  for (const unsigned int shrink : m_ShrinkFactorsPerLevel)
  {
    os << " " << shrink;
  }
  os << std::endl;
  os << indent << "Metric: " << m_Metric << std::endl;
  os << indent << "UseExactProjector: " << m_UseExactProjector << std::endl;
  os << indent << "ExactRaysPerPixelSide: " << m_ExactRaysPerPixelSide << std::endl;
  os << indent << "NumberOfSamples: " << m_NumberOfSamples << std::endl;
  os << indent << "Seed: " << m_Seed << std::endl;
  os << indent << "MaximumTimeInSeconds: " << m_MaximumTimeInSeconds << std::endl;
  os << indent << "TransferFunction: " << m_TransferFunction.GetPointer() << std::endl;
  os << indent << "ReconstructionKernel: " << m_ReconstructionKernel << std::endl;
  os << indent << "Pose (mm, degrees): " << m_Pose << std::endl;
  os << indent << "StartSimilarity: " << m_StartSimilarity << std::endl;
  os << indent << "Similarity: " << m_Similarity << std::endl;
  os << indent << "NumberOfEvaluations: " << m_NumberOfEvaluations << std::endl;
  os << indent << "ElapsedSeconds: " << m_ElapsedSeconds << std::endl;
  os << indent << "StoppedByTimeLimit: " << m_StoppedByTimeLimit << std::endl;
  os << indent << "CurrentLevel: " << m_CurrentLevel << std::endl;
}
} // namespace itk

#endif
