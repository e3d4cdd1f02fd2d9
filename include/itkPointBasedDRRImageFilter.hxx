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
#ifndef itkPointBasedDRRImageFilter_hxx
#define itkPointBasedDRRImageFilter_hxx

#include "itkPointBasedDRRImageFilter.h"
#include "itkDRRSamplerFactory.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace itk
{
template <typename TInputImage, typename TOutputImage>
PointBasedDRRImageFilter<TInputImage, TOutputImage>::PointBasedDRRImageFilter()
  : m_Sampler(DRRSamplerFactory::Create(DRRSamplerFactory::DefaultName))
  , m_Session(std::make_unique<DRRPointRenderSession>())
{
  this->SetNumberOfRequiredOutputs(2);
  this->SetNthOutput(1, this->MakeOutput(1));
}

template <typename TInputImage, typename TOutputImage>
ModifiedTimeType
PointBasedDRRImageFilter<TInputImage, TOutputImage>::GetMTime() const
{
  ModifiedTimeType latest = Superclass::GetMTime();
  if (m_Sampler)
  {
    latest = std::max(latest, m_Sampler->GetMTime());
  }
  return latest;
}

template <typename TInputImage, typename TOutputImage>
DRRPointRenderSession::Request
PointBasedDRRImageFilter<TInputImage, TOutputImage>::MakeRequest() const
{
  DRRPointRenderSession::Request request;
  request.Settings.NumberOfSamples = m_NumberOfSamples;
  request.Settings.Seed = m_Seed;
  request.Settings.Kernel = m_ReconstructionKernel;
  request.Settings.Splat = m_Splat;
  request.Settings.Weighting = m_PointWeighting;
  request.Settings.NumberOfStrata = m_NumberOfStrata;
  request.Sampler = m_Sampler.GetPointer();
  request.ControlVariateFactor = m_ControlVariateFactor;
  request.ControlVariateRaysPerSide = m_ControlVariateRaysPerSide;
  request.ComputeStandardError = m_ComputeStandardError;
  request.ReusePoints = m_ReusePoints;
  request.ExpectedNumberOfPoses = m_ExpectedNumberOfPoses;
  request.TargetError = m_TargetError;
  request.MaximumNumberOfSamples = m_MaximumNumberOfSamples;
  request.ChooseEstimator = m_ChooseEstimator;
  return request;
}

template <typename TInputImage, typename TOutputImage>
DRRPointRenderSession::Slabs
PointBasedDRRImageFilter<TInputImage, TOutputImage>::MakeSlabs()
{
  const TInputImage *          input = this->GetInput();
  const auto                   largest = input->GetLargestPossibleRegion();
  DRRPointRenderSession::Slabs slabs;
  slabs.NumberOfSlabs = this->GetNumberOfSlabs();
  slabs.Read = [this](unsigned int slab) { return this->ReadSlab(slab); };
  slabs.FirstPlane = [this, largest](unsigned int slab) {
    return static_cast<uint64_t>(this->GetSlabRegion(slab).GetIndex()[2] - largest.GetIndex()[2]);
  };
  slabs.Grid = this->MakeInputGrid();
  slabs.WholeSize = { { largest.GetSize()[0], largest.GetSize()[1], largest.GetSize()[2] } };
  slabs.MadeOf = this->GetModelMadeOfTime();
  return slabs;
}

template <typename TInputImage, typename TOutputImage>
void
PointBasedDRRImageFilter<TInputImage, TOutputImage>::PrepareSampling()
{
  this->VerifySettings(); // called before Update() too (pbdrr times it apart)
  const DRRAttenuationVolume * volume = this->GetAttenuationVolume();
  if (this->ChoosesTheEstimator())
  {
    return; // the tables wait for the choice: exact rays need none
  }
  m_Session->Prepare(this->MakeRequest(), *volume, this->MakeProjection(*volume), this->GetMultiThreader());
}

template <typename TInputImage, typename TOutputImage>
void
PointBasedDRRImageFilter<TInputImage, TOutputImage>::VerifyPreconditions() const
{
  Superclass::VerifyPreconditions();
  this->VerifySettings();
}

template <typename TInputImage, typename TOutputImage>
std::string
PointBasedDRRImageFilter<TInputImage, TOutputImage>::WhyNotStreamable() const
{
  const std::string why = Superclass::WhyNotStreamable();
  return why.empty() && m_Sampler ? DRRPointRenderSession::WhyNotStreamable(*m_Sampler) : why;
}

template <typename TInputImage, typename TOutputImage>
unsigned int
PointBasedDRRImageFilter<TInputImage, TOutputImage>::ResolveStreamedControlVariateFactor() const
{
  const TInputImage * input = this->GetInput();
  if (!input)
  {
    return 0;
  }
  const auto                    grid = this->MakeInputGrid();
  const auto                    size = input->GetLargestPossibleRegion().GetSize();
  const std::array<uint64_t, 3> wholeSize{ { size[0], size[1], size[2] } };
  return DRRPointRenderSession::ResolveStreamedFactor(
    this->MakeRequest(), *grid, wholeSize, this->MakeProjection(*grid));
}

template <typename TInputImage, typename TOutputImage>
uint64_t
PointBasedDRRImageFilter<TInputImage, TOutputImage>::GetSlabAlignment() const
{
  const uint64_t factor = this->ResolveStreamedControlVariateFactor();
  uint64_t       alignment = 8;
  while (factor > 0 && alignment % factor != 0)
  {
    alignment += 8;
  }
  return alignment;
}

template <typename TInputImage, typename TOutputImage>
bool
PointBasedDRRImageFilter<TInputImage, TOutputImage>::ReadsSlabsAtNextUpdate() const
{
  return !(m_ReusePoints && m_Session->GetRefinementSamples() == 0 && this->GetInput() &&
           m_Session->StreamedPointsAreCurrent(this->MakeRequest(), this->GetModelMadeOfTime()));
}

template <typename TInputImage, typename TOutputImage>
void
PointBasedDRRImageFilter<TInputImage, TOutputImage>::VerifySettings() const
{
  if (!m_Sampler)
  {
    itkExceptionMacro("no sampler set");
  }
  if (m_NumberOfSamples < DRRPointRenderer::MinimumNumberOfSamples)
  {
    itkExceptionMacro("the number of samples must be at least 1");
  }
  if (m_NumberOfStrata == 1)
  {
    // One stratum of dependent points has no spread to measure: its standard error would assume independence.
    itkExceptionMacro("NumberOfStrata must be 0 (the sampler's choice) or 2 to 256, not 1");
  }
  const bool chosen = m_ControlVariateFactor > 0 && m_ControlVariateFactor != AutomaticControlVariateFactor;
  if (chosen && m_ReconstructionKernel != KernelEnum::Box)
  {
    itkExceptionMacro("the control variate needs the box kernel (its coarse image is the box model's), not "
                      << m_ReconstructionKernel);
  }
  if (chosen && m_PointWeighting != WeightingEnum::Unbiased)
  {
    itkExceptionMacro("the control variate needs the unbiased point weighting (its coarse image is a line integral), "
                      "not "
                      << m_PointWeighting);
  }
  if (chosen && m_ControlVariateFactor > DRRControlVariate::MaximumFactor)
  {
    itkExceptionMacro("ControlVariateFactor must be 0 (off), 2 to " << DRRControlVariate::MaximumFactor
                                                                    << " or AutomaticControlVariateFactor, not "
                                                                    << m_ControlVariateFactor);
  }
  if (m_TargetError > 0.0 && !m_ComputeStandardError)
  {
    itkExceptionMacro("TargetError needs the standard error it is estimated from: ComputeStandardError is Off");
  }
  if (m_ChooseEstimator && !(m_TargetError > 0.0))
  {
    itkExceptionMacro("ChooseEstimator chooses the fastest estimator to a TargetError: set one above 0");
  }
  if (m_ChooseEstimator && m_PointWeighting != WeightingEnum::Unbiased)
  {
    itkExceptionMacro("ChooseEstimator needs the unbiased point weighting (its estimators are line integrals), not "
                      << m_PointWeighting);
  }
  if (m_ControlVariateFactor == 1)
  {
    itkExceptionMacro("ControlVariateFactor 1 would make the coarse image the exact one: use 0 (off), 2 to "
                      << DRRControlVariate::MaximumFactor << " or AutomaticControlVariateFactor");
  }
}

template <typename TInputImage, typename TOutputImage>
void
PointBasedDRRImageFilter<TInputImage, TOutputImage>::WarnIfTooFewPerStratum(uint64_t samples) const
{
  const uint64_t strata = DRRPointRenderer::RequestedNumberOfStrata(m_Sampler->GetTraits(), m_NumberOfStrata);
  if (strata > 1 && !DRRPointRenderer::HasEnoughSamplesPerStratum(samples, strata))
  {
    itkWarningMacro("" << samples << " samples are too few for " << strata << " strata of the "
                       << m_Sampler->GetNameOfClass()
                       << " sampler (16 per stratum at least): rendered as one run, whose standard error "
                          "treats its dependent points as independent");
  }
}

template <typename TInputImage, typename TOutputImage>
void
PointBasedDRRImageFilter<TInputImage, TOutputImage>::CompleteResult(DRRPointRenderer::Result & result) const
{
  if (result.SourceNearVolume)
  {
    itkWarningMacro("the volume reaches within " << result.MinimumDepth
                                                 << " mm of the source plane (source inside or next to the volume): "
                                                    "points nearer than that were dropped, the perspective weights "
                                                    "are very large and the standard error is unreliable there");
  }
  if (!m_ComputeStandardError)
  {
    // Not computed (the coarse image traced one replicate): zero here, for Update() and Refine() alike.
    std::fill(result.StandardError.begin(), result.StandardError.end(), 0.0);
    std::fill(result.ChannelCovariance.begin(), result.ChannelCovariance.end(), 0.0);
  }
  if (this->GetChannelLabels().size() == 1)
  {
    // One channel is the image itself.
    result.ChannelLineIntegral = result.LineIntegral;
    result.ChannelCovariance.resize(result.StandardError.size());
    std::transform(result.StandardError.begin(),
                   result.StandardError.end(),
                   result.ChannelCovariance.begin(),
                   [](double se) { return se * se; });
  }
}

template <typename TInputImage, typename TOutputImage>
void
PointBasedDRRImageFilter<TInputImage, TOutputImage>::GenerateData()
{
  const bool                     refinement = m_Session->GetRefinementSamples() > 0;
  DRRPointRenderSession::Request request = this->MakeRequest();
  uint64_t                       renderSamples = m_NumberOfSamples;
  this->UpdateProgress(0.0f);
  if (this->ChoosesTheEstimator() && !refinement)
  {
    if (this->GetChannelLabels().size() > 1)
    {
      itkExceptionMacro("ChooseEstimator renders one image, not " << this->GetChannelLabels().size()
                                                                  << " label channels: set the estimator by hand");
    }
    const DRRAttenuationVolume *        volume = this->GetAttenuationVolume();
    const DRRPointProjection            projection = this->MakeProjection(*volume);
    const DRREstimatorChoice::Candidate chosen =
      m_Session->ChooseEstimator(request, *volume, projection, this->GetMultiThreader());
    if (chosen.Kind == DRREstimatorChoice::Estimator::ExactRays)
    {
      const DRRPassCombination::Estimate exact =
        m_Session->RenderExact(request, chosen.RaysPerSide, *volume, projection, this->GetMultiThreader(), this);
      this->WriteOutputs(exact.LineIntegral, &exact.StandardError);
      this->WriteChannelOutputs(exact.ChannelLineIntegral, &exact.ChannelCovariance);
      this->UpdateProgress(1.0f);
      return;
    }
    request.ControlVariateFactor = chosen.ControlVariateFactor;
    renderSamples = chosen.NumberOfSamples;
  }
  const uint64_t               samples = m_Session->BeginPass(renderSamples);
  DRRPassCombination::Estimate estimate = this->RenderPass(request, samples);
  if (m_TargetError > 0.0 && !refinement)
  {
    estimate = this->RefineToTarget(request, std::move(estimate));
  }
  if (request.ReusePoints && this->ChoosesTheEstimator())
  {
    m_Session->SettleChoice(); // the next poses re-project these points, whatever their estimates
  }
  this->WriteOutputs(estimate.LineIntegral, &estimate.StandardError);
  this->WriteChannelOutputs(estimate.ChannelLineIntegral, &estimate.ChannelCovariance);
  this->UpdateProgress(1.0f);
}

template <typename TInputImage, typename TOutputImage>
DRRPassCombination::Estimate
PointBasedDRRImageFilter<TInputImage, TOutputImage>::RenderPass(const DRRPointRenderSession::Request & request,
                                                                uint64_t                               samples)
{
  this->WarnIfTooFewPerStratum(samples);
  DRRPointRenderer::Result result;
  if (this->GetNumberOfSlabs() > 1)
  {
    const DRRPointRenderSession::Slabs slabs = this->MakeSlabs();
    result =
      m_Session->Render(request, samples, slabs, this->MakeProjection(*slabs.Grid), this->GetMultiThreader(), this);
  }
  else
  {
    const DRRAttenuationVolume * volume = this->GetAttenuationVolume();
    result =
      m_Session->Render(request, samples, *volume, this->MakeProjection(*volume), this->GetMultiThreader(), this);
  }
  this->CompleteResult(result);
  return m_Session->AddPass(result, samples);
}

template <typename TInputImage, typename TOutputImage>
DRRPassCombination::Estimate
PointBasedDRRImageFilter<TInputImage, TOutputImage>::RefineToTarget(const DRRPointRenderSession::Request & request,
                                                                    DRRPassCombination::Estimate           estimate)
{
  // The error of independent passes falls as 1 / sqrt(points): the points missing for the target, a tenth more so
  // that an estimate a little low does not cost a pass of a few points (DRRRefinementTrend::GetGrowthToTarget()).
  // Every pass adds at least a tenth of the points, so the passes end, at the target or at MaximumNumberOfSamples.
  // Chosen kept points are drawn again, more of them, at the choice's first pose: the poses after it re-project
  // them alone, whatever their estimates, so that every pose's image is a function of the first pose and its own.
  const bool chosenKeptPoints = request.ReusePoints && this->ChoosesTheEstimator();
  if (chosenKeptPoints && m_Session->IsChoiceSettled())
  {
    return estimate;
  }
  const bool         drawAgain = chosenKeptPoints;
  DRRRefinementTrend trend;
  for (double error = m_Session->GetEstimatedError(); error > m_TargetError; error = m_Session->GetEstimatedError())
  {
    const double total = static_cast<double>(m_Session->GetPasses().GetNumberOfSamples());
    if (trend.AddEstimate(total, error) && this->ChoosesTheEstimator())
    {
      // What is left is not the points' to lower: the exact rays that reach the target instead.
      return this->RenderExactInstead(request);
    }
    // Kept points are one pass, its coarse image's rays fixed: its error stays (passes each trace their own).
    const double coarse = drawAgain ? std::min(m_Session->GetCoarseImageError(), error) : 0.0;
    if (drawAgain && coarse > DRRRefinementTrend::LargestCoarseShare * m_TargetError)
    {
      // The coarse image's rays alone are near the target: kept points would need many times more (their part must
      // fall to sqrt(t^2 - c^2)). The exact rays that reach the target instead.
      return this->RenderExactInstead(request);
    }
    const double wanted = std::ceil(total * DRRRefinementTrend::GetGrowthToTarget(error, coarse, m_TargetError));
    if (!(wanted <= static_cast<double>(m_MaximumNumberOfSamples)))
    {
      itkExceptionMacro("the target error " << m_TargetError << " is not reached within MaximumNumberOfSamples "
                                            << m_MaximumNumberOfSamples << ": the estimated error is " << error
                                            << " at " << total << " points, and about " << wanted
                                            << " would be needed");
    }
    if (drawAgain)
    {
      m_Session->RaiseChosenSamples(static_cast<uint64_t>(wanted));
      estimate = this->RenderPass(request, m_Session->BeginPass(static_cast<uint64_t>(wanted)));
      continue;
    }
    estimate = this->RenderPass(request, static_cast<uint64_t>(wanted - total));
  }
  return estimate;
}

template <typename TInputImage, typename TOutputImage>
DRRPassCombination::Estimate
PointBasedDRRImageFilter<TInputImage, TOutputImage>::RenderExactInstead(const DRRPointRenderSession::Request & request)
{
  const DRRAttenuationVolume *        volume = this->GetAttenuationVolume();
  const DRREstimatorChoice::Candidate exact = m_Session->FallBackToExactRays(request);
  return m_Session->RenderExact(
    request, exact.RaysPerSide, *volume, this->MakeProjection(*volume), this->GetMultiThreader(), this);
}

template <typename TInputImage, typename TOutputImage>
const DRREstimatorChoice::Candidate &
PointBasedDRRImageFilter<TInputImage, TOutputImage>::MakeEstimatorChoice()
{
  this->VerifyEstimatorChoice();
  const DRRAttenuationVolume * volume = this->GetAttenuationVolume();
  return m_Session->ChooseEstimator(
    this->MakeRequest(), *volume, this->MakeProjection(*volume), this->GetMultiThreader());
}

template <typename TInputImage, typename TOutputImage>
const DRREstimatorChoice::Candidate &
PointBasedDRRImageFilter<TInputImage, TOutputImage>::MakeEstimatorChoice(const DRREstimatorChoice & pilots)
{
  this->VerifyEstimatorChoice();
  return m_Session->ChooseEstimator(this->MakeRequest(), *this->GetAttenuationVolume(), pilots);
}

template <typename TInputImage, typename TOutputImage>
DRREstimatorChoice
PointBasedDRRImageFilter<TInputImage, TOutputImage>::MeasureEstimatorChoice()
{
  this->VerifyEstimatorChoice();
  const DRRAttenuationVolume * volume = this->GetAttenuationVolume();
  DRREstimatorChoice           pilot;
  pilot.Measure(*volume, m_ReconstructionKernel, this->MakeProjection(*volume), this->GetMultiThreader());
  return pilot;
}

template <typename TInputImage, typename TOutputImage>
void
PointBasedDRRImageFilter<TInputImage, TOutputImage>::VerifyEstimatorChoice()
{
  this->VerifySettings();
  if (!this->ChoosesTheEstimator())
  {
    itkExceptionMacro("a choice of estimator needs ChooseEstimator, a TargetError and the whole volume");
  }
}

template <typename TInputImage, typename TOutputImage>
bool
PointBasedDRRImageFilter<TInputImage, TOutputImage>::ChoosesTheEstimator() const
{
  return m_ChooseEstimator && m_TargetError > 0.0 && this->GetNumberOfSlabs() <= 1;
}

template <typename TInputImage, typename TOutputImage>
void
PointBasedDRRImageFilter<TInputImage, TOutputImage>::Refine(uint64_t additionalSamples)
{
  if (additionalSamples < DRRPointRenderer::MinimumNumberOfSamples)
  {
    itkExceptionMacro("the number of samples must be at least 1");
  }
  // Anything upstream of the outputs newer than them (the filter's settings, geometry, transform, sampler, the input
  // or attenuation volume, modified in place or not) makes a refinement of another image.
  this->UpdateOutputInformation();
  m_Session->RequestRefinement(additionalSamples, this->GetOutput()->GetPipelineMTime());
  this->Modified(); // the outputs are written by Update() alone
  try
  {
    this->Update();
  }
  catch (...)
  {
    m_Session->CancelRefinement();
    throw;
  }
}

template <typename TInputImage, typename TOutputImage>
void
PointBasedDRRImageFilter<TInputImage, TOutputImage>::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "NumberOfSamples: " << m_NumberOfSamples << std::endl;
  os << indent << "Seed: " << m_Seed << std::endl;
  os << indent << "ReconstructionKernel: " << m_ReconstructionKernel << std::endl;
  os << indent << "Splat: " << m_Splat << std::endl;
  os << indent << "PointWeighting: " << m_PointWeighting << std::endl;
  os << indent << "NumberOfStrata: " << m_NumberOfStrata << std::endl;
  os << indent << "ControlVariateFactor: "
     << (m_ControlVariateFactor == AutomaticControlVariateFactor ? std::string("auto")
                                                                 : std::to_string(m_ControlVariateFactor))
     << std::endl;
  os << indent << "ControlVariateRaysPerSide: " << m_ControlVariateRaysPerSide << std::endl;
  os << indent << "ComputeStandardError: " << (m_ComputeStandardError ? "On" : "Off") << std::endl;
  os << indent << "TargetError: " << m_TargetError << std::endl;
  os << indent << "MaximumNumberOfSamples: " << m_MaximumNumberOfSamples << std::endl;
  os << indent << "ChooseEstimator: " << (m_ChooseEstimator ? "On" : "Off") << std::endl;
  os << indent << "EstimatedError: " << this->GetEstimatedError() << std::endl;
  os << indent << "Sampler: " << (m_Sampler ? m_Sampler->GetNameOfClass() : "(none)") << std::endl;
  os << indent << "TotalMass (mm^2): " << this->GetTotalMass() << std::endl;
  os << indent << "PointsOnDetector: " << this->GetPointsOnDetector() << std::endl;
  os << indent << "TotalNumberOfSamples: " << this->GetTotalNumberOfSamples() << std::endl;
  os << indent << "NumberOfPasses: " << m_Session->GetPasses().GetNumberOfPasses() << std::endl;
  os << indent << "ReusePoints: " << (m_ReusePoints ? "On" : "Off") << std::endl;
  os << indent << "ExpectedNumberOfPoses: " << m_ExpectedNumberOfPoses << std::endl;
  os << indent << "PointCloud: ";
  if (const DRRPointCloud * cloud = this->GetPointCloud())
  {
    os << cloud->GetNumberOfPoints() << " points, " << cloud->GetBytesPerPoint() << " bytes per point" << std::endl;
  }
  else
  {
    os << "(none)" << std::endl;
  }
}
} // namespace itk

#endif
