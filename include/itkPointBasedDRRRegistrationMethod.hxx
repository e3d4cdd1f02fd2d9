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

#include "itkAmoebaOptimizerv4.h"
#include "itkConjugateGradientLineSearchOptimizerv4.h"
#include "itkLBFGSBOptimizerv4.h"
#include "itkMatrixOffsetTransformBase.h"
#include "itkPowellOptimizerv4.h"
#include "itkRegularStepGradientDescentOptimizerv4.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace itk
{
template <typename TInputImage>
const std::vector<std::string> &
PointBasedDRRRegistrationMethod<TInputImage>::GetOptimizerNames()
{
  static const std::vector<std::string> names{ "rsgd", "lbfgsb", "cg", "powell", "amoeba" };
  return names;
}

template <typename TInputImage>
auto
PointBasedDRRRegistrationMethod<TInputImage>::MakeOptimizer(const std::string & name) -> typename OptimizerType::Pointer
{
  // Every length below is in mm of the points' motion: the method presents the parameters so (DeadlineMetric).
  if (name == "rsgd")
  {
    // Steps of 2 mm, halved whenever the gradient turns back, down to 0.01 mm.
    auto optimizer = RegularStepGradientDescentOptimizerv4<double>::New();
    optimizer->SetLearningRate(2.0);
    optimizer->SetMinimumStepLength(0.01);
    optimizer->SetRelaxationFactor(0.5);
    optimizer->SetGradientMagnitudeTolerance(1e-12);
    optimizer->SetNumberOfIterations(200);
    optimizer->SetReturnBestParametersAndValue(true);
    return optimizer.GetPointer();
  }
  if (name == "lbfgsb")
  {
    auto                                  optimizer = LBFGSBOptimizerv4::New();
    LBFGSBOptimizerv4::BoundSelectionType unbounded(6);
    unbounded.Fill(0);
    optimizer->SetBoundSelection(unbounded);
    optimizer->SetCostFunctionConvergenceFactor(1e9);
    optimizer->SetGradientConvergenceTolerance(1e-7);
    optimizer->SetNumberOfIterations(100);
    optimizer->SetMaximumNumberOfFunctionEvaluations(200);
    optimizer->SetMaximumNumberOfCorrections(6);
    return optimizer.GetPointer();
  }
  if (name == "cg")
  {
    // A golden-section line search along each conjugate direction, over steps of up to 5 mm.
    auto optimizer = ConjugateGradientLineSearchOptimizerv4::New();
    optimizer->SetLearningRate(1.0);
    optimizer->SetLowerLimit(0.0);
    optimizer->SetUpperLimit(5.0);
    optimizer->SetEpsilon(0.01);
    optimizer->SetMaximumLineSearchIterations(12);
    optimizer->SetNumberOfIterations(30);
    optimizer->SetMinimumConvergenceValue(1e-6);
    optimizer->SetConvergenceWindowSize(5);
    optimizer->SetDoEstimateLearningRateAtEachIteration(false);
    optimizer->SetDoEstimateLearningRateOnce(false);
    optimizer->SetReturnBestParametersAndValue(true);
    return optimizer.GetPointer();
  }
  if (name == "powell")
  {
    // As the earlier, derivative-free registration: steps of 2 mm, to 0.02 mm.
    auto optimizer = PowellOptimizerv4<double>::New();
    optimizer->SetStepLength(2.0);
    optimizer->SetStepTolerance(0.02);
    optimizer->SetValueTolerance(1e-7);
    optimizer->SetMaximumIteration(8);
    optimizer->SetMaximumLineIteration(12);
    return optimizer.GetPointer();
  }
  if (name == "amoeba")
  {
    auto                              optimizer = AmoebaOptimizerv4::New();
    AmoebaOptimizerv4::ParametersType simplex(6);
    simplex.Fill(2.0);
    optimizer->SetInitialSimplexDelta(simplex);
    optimizer->SetParametersConvergenceTolerance(0.02);
    optimizer->SetFunctionConvergenceTolerance(1e-6);
    optimizer->SetNumberOfIterations(400);
    return optimizer.GetPointer();
  }
  std::string names;
  for (const std::string & known : GetOptimizerNames())
  {
    names += (names.empty() ? "" : ", ") + known;
  }
  itkGenericExceptionMacro("unknown optimizer '" << name << "' (" << names << ")");
}

template <typename TInputImage>
PointBasedDRRRegistrationMethod<TInputImage>::PointBasedDRRRegistrationMethod() : m_Metric(MetricType::New())
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
void
PointBasedDRRRegistrationMethod<TInputImage>::SetNumberOfSamplesPerLevel(const SamplesArrayType & samples)
{
  if (samples != m_NumberOfSamplesPerLevel)
  {
    m_NumberOfSamplesPerLevel = samples;
    this->Modified();
  }
}

template <typename TInputImage>
void
PointBasedDRRRegistrationMethod<TInputImage>::SetSmoothingSigmasPerLevel(const SmoothingSigmasArrayType & sigmas)
{
  if (sigmas != m_SmoothingSigmasPerLevel)
  {
    m_SmoothingSigmasPerLevel = sigmas;
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
  latest = m_Metric ? std::max(latest, m_Metric->GetMTime()) : latest;
  return m_Optimizer ? std::max(latest, m_Optimizer->GetMTime()) : latest;
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
void
PointBasedDRRRegistrationMethod<TInputImage>::SetMovingTransformToPose(const PoseType & pose) const
{
  using LinearType = MatrixOffsetTransformBase<double, 3, 3>;
  auto * moving = dynamic_cast<LinearType *>(m_Metric->GetModifiableMovingTransform());
  if (!moving)
  {
    itkExceptionMacro("the metric's moving transform is a "
                      << m_Metric->GetModifiableMovingTransform()->GetNameOfClass()
                      << ": the method starts and reports poses of a MatrixOffsetTransformBase (Euler3DTransform, "
                         "VersorRigid3DTransform, ...)");
  }
  // The moving transform maps the room to the CT: the inverse of the pose, about the same centre.
  const auto forward = MakePoseTransform(this->GetVolume(), pose);
  auto       inverse = TransformType::New();
  forward->GetInverse(inverse);
  moving->SetCenter(forward->GetCenter());
  moving->SetMatrix(inverse->GetMatrix());
  moving->SetOffset(inverse->GetOffset());
}

template <typename TInputImage>
auto
PointBasedDRRRegistrationMethod<TInputImage>::PoseOfMovingTransform() const -> PoseType
{
  using LinearType = MatrixOffsetTransformBase<double, 3, 3>;
  const auto * moving = dynamic_cast<const LinearType *>(m_Metric->GetModifiableMovingTransform());
  auto         inverse = LinearType::New();
  moving->GetInverse(inverse);
  auto pose = TransformType::New();
  pose->SetCenter(GeometryType::ComputeImageCenter(this->GetVolume()));
  pose->SetMatrix(inverse->GetMatrix());
  pose->SetOffset(inverse->GetOffset());
  return ToPose(pose->GetParameters());
}

template <typename TInputImage>
auto
PointBasedDRRRegistrationMethod<TInputImage>::GlobalStart(unsigned int k) const -> PoseType
{
  if (k == 0)
  {
    return m_StartPose;
  }
  // Deterministic and spread: the k-th point of a Halton sequence in bases 2, 3, 5, 7, 11, 13 over the cube of side
  // twice the radius about the start pose (mm, degrees).
  static const unsigned int bases[6] = { 2, 3, 5, 7, 11, 13 };
  PoseType                  start = m_StartPose;
  for (unsigned int d = 0; d < 6; ++d)
  {
    double fraction = 1.0, value = 0.0;
    for (unsigned int i = k; i > 0; i /= bases[d])
    {
      fraction /= bases[d];
      value += fraction * (i % bases[d]);
    }
    start[d] += m_StartRadius * (2.0 * value - 1.0);
  }
  return start;
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
  if (!m_Metric)
  {
    itkExceptionMacro("no metric (SetMetric())");
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
  const size_t levels = m_ShrinkFactorsPerLevel.size();
  if (!m_NumberOfSamplesPerLevel.empty() && m_NumberOfSamplesPerLevel.size() != levels)
  {
    itkExceptionMacro("the schedule has " << levels << " levels but " << m_NumberOfSamplesPerLevel.size()
                                          << " numbers of samples: give one per level, or none (a new schedule keeps "
                                             "the per-level points and smoothing)");
  }
  if (!m_SmoothingSigmasPerLevel.empty() && m_SmoothingSigmasPerLevel.size() != levels)
  {
    itkExceptionMacro("the schedule has " << levels << " levels but " << m_SmoothingSigmasPerLevel.size()
                                          << " smoothing sigmas: give one per level, or none (a new schedule keeps "
                                             "the per-level points and smoothing)");
  }
  if (!(m_MaximumTimeInSeconds >= 0.0))
  {
    itkExceptionMacro("the time limit is " << m_MaximumTimeInSeconds << " s: give 0 (none) or a positive number");
  }
  if (!(m_StartRadius >= 0.0) || !std::isfinite(m_StartRadius))
  {
    itkExceptionMacro("the start radius is " << m_StartRadius << ": give 0 or more (mm and degrees)");
  }
}

template <typename TInputImage>
auto
PointBasedDRRRegistrationMethod<TInputImage>::Optimize(OptimizerType *  optimizer,
                                                       DeadlineMetric * watched,
                                                       double & bestValue) -> typename MetricType::ParametersType
{
  if (auto * lbfgsb = dynamic_cast<LBFGSBOptimizerv4 *>(optimizer))
  {
    lbfgsb->SetInitialPosition(watched->GetParameters()); // it keeps its last start otherwise
  }
  optimizer->SetMetric(watched);
  optimizer->StartOptimization();
  m_CurrentStopCondition = optimizer->GetStopConditionDescription();
  // The position the optimizer ended at may not be the best it evaluated (a last failed step, a line search): keep the
  // best, evaluating the end if it was not.
  if (!watched->GetTimeIsUp())
  {
    typename MetricType::ParametersType end = watched->GetParameters();
    watched->SetParameters(end);
    watched->GetValue();
  }
  bestValue = watched->GetBestValue();
  return watched->GetBestParameters();
}

template <typename TInputImage>
void
PointBasedDRRRegistrationMethod<TInputImage>::GenerateData()
{
  const auto begin = std::chrono::steady_clock::now();
  const auto deadline = m_MaximumTimeInSeconds > 0.0
                          ? begin + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                      std::chrono::duration<double>(m_MaximumTimeInSeconds))
                          : std::chrono::steady_clock::time_point::max();
  m_NumberOfEvaluations = 0;
  m_NumberOfDerivativeEvaluations = 0;
  m_StoppedByTimeLimit = false;
  m_FinalDRRs.clear();
  m_FinalMasks.clear();
  this->PrepareMetric();
  const uint64_t                  metricSamples = m_Metric->GetNumberOfSamples();
  typename OptimizerType::Pointer optimizer = m_Optimizer;
  if (!optimizer)
  {
    optimizer = MakeOptimizer(m_Metric->GetExactRaysPerPixelSide() > 0 ? "powell" : DefaultOptimizerName);
  }
  auto watched = DeadlineMetric::New();
  for (unsigned int level = 0; level < m_ShrinkFactorsPerLevel.size() && !m_StoppedByTimeLimit; ++level)
  {
    this->InitializeLevel(level, metricSamples);
    this->RegisterLevel(level, optimizer, *watched, deadline);
  }
  m_Pose = this->PoseOfMovingTransform();
  this->MakeFinalImages();
  m_Metric->SetNumberOfSamples(metricSamples);
  auto * output = static_cast<DecoratedTransformType *>(this->ProcessObject::GetOutput(0));
  output->Set(MakePoseTransform(this->GetVolume(), m_Pose));
  m_ElapsedSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
}

template <typename TInputImage>
void
PointBasedDRRRegistrationMethod<TInputImage>::PrepareMetric()
{
  const InputImageType * volume = this->GetVolume();
  m_Metric->SetVolume(volume);
  m_Metric->RemoveAllXRays();
  for (unsigned int x = 0; x < m_XRayGeometries.size(); ++x)
  {
    m_Metric->AddXRay(this->GetXRayImage(x), m_XRayGeometries[x]);
  }
  m_Metric->SetNumberOfWorkUnits(this->GetNumberOfWorkUnits());
  if (!m_Metric->GetModifiableMovingTransform())
  {
    auto moving = Euler3DTransform<double>::New();
    moving->SetCenter(GeometryType::ComputeImageCenter(volume));
    m_Metric->SetMovingTransform(moving);
  }
  this->SetMovingTransformToPose(m_StartPose);
}

template <typename TInputImage>
void
PointBasedDRRRegistrationMethod<TInputImage>::InitializeLevel(unsigned int level, uint64_t metricSamples)
{
  m_Metric->SetDetectorShrinkFactor(m_ShrinkFactorsPerLevel[level]);
  m_Metric->SetNumberOfSamples(m_NumberOfSamplesPerLevel.empty() ? metricSamples : m_NumberOfSamplesPerLevel[level]);
  m_Metric->SetSmoothingSigma(m_SmoothingSigmasPerLevel.empty() ? 0.0 : m_SmoothingSigmasPerLevel[level]);
  m_Metric->Initialize();
  if (level == 0)
  {
    m_StartSimilarity = -m_Metric->GetValue(); // outside the search and its time limit
  }
}

template <typename TInputImage>
Array<double>
PointBasedDRRRegistrationMethod<TInputImage>::ComputeParameterUnits() const
{
  Array<double> units;
  if (m_AutomaticParameterScales)
  {
    const auto scales = m_Metric->ComputeParameterScales();
    units.SetSize(scales.GetSize());
    for (unsigned int j = 0; j < scales.GetSize(); ++j)
    {
      units[j] = std::sqrt(std::max(scales[j], 1e-12));
    }
  }
  return units;
}

template <typename TInputImage>
void
PointBasedDRRRegistrationMethod<TInputImage>::RegisterLevel(unsigned int                          level,
                                                            OptimizerType *                       optimizer,
                                                            DeadlineMetric &                      watched,
                                                            std::chrono::steady_clock::time_point deadline)
{
  const Array<double> units = this->ComputeParameterUnits();
  const auto          account = [&]() {
    m_NumberOfEvaluations += watched.GetEvaluations();
    m_NumberOfDerivativeEvaluations += watched.GetDerivativeEvaluations();
    m_StoppedByTimeLimit = m_StoppedByTimeLimit || watched.GetTimeIsUp();
    return watched.GetEvaluations();
  };
  watched.Watch(m_Metric, units, deadline);
  // The global stage on the first level: the best end of several starts goes on. If nothing was evaluated (the
  // time limit), the level's start stands: an optimizer may have moved the transform on values it was not given.
  const unsigned int                  starts = level == 0 ? m_NumberOfStarts : 1;
  double                              best = std::numeric_limits<double>::infinity();
  typename MetricType::ParametersType levelStart = m_Metric->GetParameters();
  typename MetricType::ParametersType bestParameters = levelStart;
  SizeValueType                       levelEvaluations = 0;
  for (unsigned int k = 0; k < starts && !watched.GetTimeIsUp(); ++k)
  {
    if (k > 0)
    {
      levelEvaluations += account();
      this->SetMovingTransformToPose(this->GlobalStart(k));
      watched.Watch(m_Metric, units, deadline);
    }
    double                                    value = best;
    const typename MetricType::ParametersType found = this->Optimize(optimizer, &watched, value);
    if (value < best)
    {
      best = value;
      bestParameters = found;
    }
  }
  levelEvaluations += account();
  m_Metric->SetParameters(std::isfinite(best) ? bestParameters : levelStart);
  m_CurrentLevel = level;
  m_CurrentShrinkFactor = m_ShrinkFactorsPerLevel[level];
  m_CurrentLevelSimilarity = -best;
  m_CurrentLevelEvaluations = levelEvaluations;
  m_CurrentPose = this->PoseOfMovingTransform();
  this->InvokeEvent(IterationEvent());
  this->UpdateProgress(static_cast<float>(level + 1) / static_cast<float>(m_ShrinkFactorsPerLevel.size()));
}

template <typename TInputImage>
void
PointBasedDRRRegistrationMethod<TInputImage>::MakeFinalImages()
{
  // The final DRRs and similarity, at full resolution, unsmoothed, with the last level's points.
  m_Metric->SetDetectorShrinkFactor(1);
  m_Metric->SetSmoothingSigma(0.0);
  m_Metric->Initialize();
  m_Similarity = -m_Metric->GetValue();
  for (unsigned int x = 0; x < m_XRayGeometries.size(); ++x)
  {
    m_FinalDRRs.push_back(m_Metric->ComputeDRR(x));
    m_FinalMasks.push_back(m_Metric->GetField(x));
  }
}

template <typename TInputImage>
void
PointBasedDRRRegistrationMethod<TInputImage>::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "NumberOfXRays: " << m_XRayGeometries.size() << std::endl;
  os << indent << "Metric: " << m_Metric.GetPointer() << std::endl;
  os << indent << "Optimizer: " << (m_Optimizer ? m_Optimizer->GetNameOfClass() : "(default)") << std::endl;
  os << indent << "AutomaticParameterScales: " << m_AutomaticParameterScales << std::endl;
  os << indent << "StartPose (mm, degrees): " << m_StartPose << std::endl;
  os << indent << "ShrinkFactorsPerLevel:";
  for (const unsigned int shrink : m_ShrinkFactorsPerLevel)
  {
    os << " " << shrink;
  }
  os << std::endl << indent << "NumberOfSamplesPerLevel:";
  for (const uint64_t samples : m_NumberOfSamplesPerLevel)
  {
    os << " " << samples;
  }
  os << std::endl << indent << "SmoothingSigmasPerLevel (mm):";
  for (const double sigma : m_SmoothingSigmasPerLevel)
  {
    os << " " << sigma;
  }
  os << std::endl;
  os << indent << "NumberOfStarts: " << m_NumberOfStarts << std::endl;
  os << indent << "StartRadius (mm, degrees): " << m_StartRadius << std::endl;
  os << indent << "MaximumTimeInSeconds: " << m_MaximumTimeInSeconds << std::endl;
  os << indent << "Pose (mm, degrees): " << m_Pose << std::endl;
  os << indent << "StartSimilarity: " << m_StartSimilarity << std::endl;
  os << indent << "Similarity: " << m_Similarity << std::endl;
  os << indent << "NumberOfEvaluations: " << m_NumberOfEvaluations << std::endl;
  os << indent << "NumberOfDerivativeEvaluations: " << m_NumberOfDerivativeEvaluations << std::endl;
  os << indent << "ElapsedSeconds: " << m_ElapsedSeconds << std::endl;
  os << indent << "StoppedByTimeLimit: " << m_StoppedByTimeLimit << std::endl;
  os << indent << "CurrentLevel: " << m_CurrentLevel << std::endl;
}
} // namespace itk

#endif
