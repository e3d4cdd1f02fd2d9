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
#include <utility>

namespace itk
{
template <typename TInputImage, typename TOutputImage>
PointBasedDRRImageFilter<TInputImage, TOutputImage>::PointBasedDRRImageFilter()
  : m_Sampler(DRRSamplerFactory::Create(DRRSamplerFactory::DefaultName))
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
unsigned int
PointBasedDRRImageFilter<TInputImage, TOutputImage>::ResolveControlVariateFactor()
{
  const DRRAttenuationVolume * volume = this->GetAttenuationVolume();
  if (volume->GetNumberOfChannels() > 1)
  {
    // The coarse image mixes the labels of a block: channels render without a control variate.
    if (m_ControlVariateFactor != 0 && m_ControlVariateFactor != AutomaticControlVariateFactor)
    {
      itkExceptionMacro("label channels are rendered without a control variate (its coarse blocks mix labels): set "
                        "ControlVariateFactor to 0 or AutomaticControlVariateFactor, not "
                        << m_ControlVariateFactor);
    }
    return 0;
  }
  if (m_ControlVariateFactor != AutomaticControlVariateFactor)
  {
    return m_ControlVariateFactor;
  }
  if (m_ReusePoints && m_PreparedFactor != 0 && m_PreparedVolume == volume &&
      m_ControlVariateTime.GetMTime() > volume->GetMTime())
  {
    return m_PreparedFactor; // kept points: one split (or its decline) for every pose, chosen at the first
  }
  return DRRControlVariate::ChooseFactor(
    *volume, this->MakeProjection(), m_NumberOfSamples, m_ReusePoints ? m_ExpectedNumberOfPoses : 1);
}

template <typename TInputImage, typename TOutputImage>
void
PointBasedDRRImageFilter<TInputImage, TOutputImage>::PrepareControlVariate()
{
  const DRRAttenuationVolume * volume = this->GetAttenuationVolume();
  const unsigned int           factor = this->ResolveControlVariateFactor();
  if (m_PreparedVolume == volume && m_ControlVariateTime.GetMTime() > volume->GetMTime() && m_PreparedFactor == factor)
  {
    return; // made, or declined, for this volume and factor already
  }
  m_ControlVariate = nullptr; // its tables are large: free the old split before making the new one
  m_PreparedVolume = volume;
  m_PreparedFactor = factor;
  if (factor != 0)
  {
    m_ControlVariate = DRRControlVariate::New();
    m_ControlVariate->Build(*volume, factor, this->GetMultiThreader());
  }
  m_ControlVariateTime.Modified();
}

template <typename TInputImage, typename TOutputImage>
const DRRAttenuationVolume &
PointBasedDRRImageFilter<TInputImage, TOutputImage>::GetSamplingVolume() const
{
  return m_ControlVariate ? m_ControlVariate->GetResidualVolume() : *m_PreparedVolume;
}

template <typename TInputImage, typename TOutputImage>
void
PointBasedDRRImageFilter<TInputImage, TOutputImage>::PrepareSampling()
{
  this->VerifySettings(m_NumberOfSamples); // called before Update() too (pbdrr times it apart)
  this->PrepareControlVariate();
  this->InitializeSampler(this->GetSamplingVolume());
  if (m_ControlVariateFactor == AutomaticControlVariateFactor && m_ControlVariate &&
      m_Sampler->GetTotalMass() > MaximumAutomaticResidualFraction * m_ControlVariate->GetTotalMass())
  {
    // The residual holds more than the stated fraction of the mass (M_r as the sampler summed it, no pass of its
    // own): the points' error would shrink by less than the coarse image costs (or grow, above 1). `auto` renders
    // without a control variate, and remembers the F it declined for this volume (m_PreparedFactor).
    itkDebugMacro("control variate F " << m_ControlVariate->GetFactor() << " declined: M_r / M = "
                                       << m_Sampler->GetTotalMass() / m_ControlVariate->GetTotalMass());
    m_ControlVariate = nullptr;
    m_ControlVariateTime.Modified();
    this->InitializeSampler(this->GetSamplingVolume());
  }
}

template <typename TInputImage, typename TOutputImage>
void
PointBasedDRRImageFilter<TInputImage, TOutputImage>::InitializeSampler(const DRRAttenuationVolume & volume)
{
  // The sampler's tables are stale once anything they are made of is newer: the volume sampled, the control variate
  // (made or declined: another volume sampled), the sampler's own settings, or the sampler set.
  const ModifiedTimeType madeOf = std::max(
    { volume.GetMTime(), m_ControlVariateTime.GetMTime(), m_Sampler->GetMTime(), m_SamplingSettingsTime.GetMTime() });
  if (madeOf > m_SamplerTime.GetMTime())
  {
    m_Sampler->Initialize(volume);
    m_SamplerTime.Modified();
  }
}

template <typename TInputImage, typename TOutputImage>
void
PointBasedDRRImageFilter<TInputImage, TOutputImage>::AddControlVariateImage(const DRRPointRenderer::Settings & settings,
                                                                            DRRPointRenderer::Result &         result)
{
  if (m_ControlVariate)
  {
    this->AddCoarseImage(*m_ControlVariate, this->MakeProjection(), settings, result);
  }
}

template <typename TInputImage, typename TOutputImage>
void
PointBasedDRRImageFilter<TInputImage, TOutputImage>::AddCoarseImage(const DRRControlVariate &          controlVariate,
                                                                    const DRRPointProjection &         projection,
                                                                    const DRRPointRenderer::Settings & settings,
                                                                    DRRPointRenderer::Result &         result)
{
  controlVariate.AddCoarseImage(projection,
                                settings.Splat,
                                m_ControlVariateRaysPerSide,
                                settings.Seed,
                                this->GetMultiThreader(),
                                this,
                                result,
                                m_ComputeStandardError ? 2u : 1u);
}

template <typename TInputImage, typename TOutputImage>
void
PointBasedDRRImageFilter<TInputImage, TOutputImage>::VerifyPreconditions() const
{
  Superclass::VerifyPreconditions();
  this->VerifySettings(m_RefinementSamples > 0 ? m_RefinementSamples : m_NumberOfSamples);
}

template <typename TInputImage, typename TOutputImage>
std::string
PointBasedDRRImageFilter<TInputImage, TOutputImage>::WhyNotStreamable() const
{
  const std::string why = Superclass::WhyNotStreamable();
  if (!why.empty())
  {
    return why;
  }
  if (m_Sampler && !dynamic_cast<const DRRStratifiedSampler *>(m_Sampler.GetPointer()))
  {
    return "streaming shares the points out between the slabs along the stratified sampler's curve (the unstreamed "
           "render's points); " +
           std::string(m_Sampler->GetNameOfClass()) +
           " draws its voxels from tables of the whole volume: use the stratified sampler";
  }
  return {};
}

template <typename TInputImage, typename TOutputImage>
unsigned int
PointBasedDRRImageFilter<TInputImage, TOutputImage>::ResolveStreamedControlVariateFactor() const
{
  if (m_ControlVariateFactor != AutomaticControlVariateFactor)
  {
    return m_ControlVariateFactor;
  }
  const TInputImage * input = this->GetInput();
  if (!input)
  {
    return 0;
  }
  const auto                     grid = this->MakeInputGrid();
  const auto                     size = input->GetLargestPossibleRegion().GetSize();
  DRRAttenuationVolume::SizeType wholeSize{ { size[0], size[1], size[2] } };
  const unsigned int             factor = DRRControlVariate::ChooseFactor(wholeSize,
                                                              grid->GetVoxelVolume(),
                                                              this->MakeProjection(*grid),
                                                              m_NumberOfSamples,
                                                              m_ReusePoints ? m_ExpectedNumberOfPoses : 1);
  return std::max(factor, MinimumStreamedAutomaticFactor);
}

template <typename TInputImage, typename TOutputImage>
uint64_t
PointBasedDRRImageFilter<TInputImage, TOutputImage>::GetSlabAlignment() const
{
  // Whole brick planes, and whole coarse blocks: lcm(8, F).
  const uint64_t factor = this->ResolveStreamedControlVariateFactor();
  uint64_t       alignment = 8;
  while (factor > 0 && alignment % factor != 0)
  {
    alignment += 8;
  }
  return alignment;
}

template <typename TInputImage, typename TOutputImage>
DRRPointRenderer::Result
PointBasedDRRImageFilter<TInputImage, TOutputImage>::RenderStreamed(const DRRPointRenderer::Settings & settings,
                                                                    bool                               keepPoints)
{
  using Placement = DRRStratifiedSampler::SlabPlacement;
  if (!dynamic_cast<const DRRStratifiedSampler *>(m_Sampler.GetPointer()))
  {
    itkExceptionMacro("streaming needs the stratified sampler");
  }
  // Samplers of the slabs' own: the filter's keeps its tables of the whole volume (if any) for unstreamed renders.
  DRRStratifiedSampler::Pointer sampler;
  MultiThreaderBase *           threader = this->GetMultiThreader();
  const unsigned int            slabs = this->GetNumberOfSlabs();
  const auto                    grid = this->MakeInputGrid();
  const DRRPointProjection      projection = this->MakeProjection(*grid);
  const auto                    size = this->GetInput()->GetLargestPossibleRegion().GetSize();
  const std::array<uint64_t, 3> wholeSize{ { size[0], size[1], size[2] } };
  unsigned int                  factor = this->ResolveStreamedControlVariateFactor();
  const auto                    firstPlaneOf = [&](unsigned int slab) {
    return static_cast<uint64_t>(this->GetSlabRegion(slab).GetIndex()[2] -
                                 this->GetInput()->GetLargestPossibleRegion().GetIndex()[2]);
  };
  // Kept points serve every view: the whole volume's plan, not culled.
  const auto planOf = [&](const Placement & placement) {
    return keepPoints ? sampler->MakeSlabViewPlan(nullptr, 0.0, 0.0, placement)
                      : DRRStreamedPointRender::MakeSlabPlan(*sampler, projection, settings, placement);
  };
  const auto checkAbort = [&]() {
    if (this->GetAbortGenerateData())
    {
      ProcessAborted aborted(__FILE__, __LINE__);
      aborted.SetDescription("the streamed render was aborted between slabs");
      throw aborted;
    }
  };
  // A slab's model, its control variate (its own residual; its coarse planes are the whole one's) and the sampler's
  // tables of what it samples.
  DRRAttenuationVolume::Pointer slabVolume;
  DRRControlVariate::Pointer    slabControlVariate;
  const auto                    prepareSlab = [&](unsigned int slab) {
    // The last slab's tables and model go before this one is read: they hold its voxels (the model reads them in
    // place), which would otherwise stay beside the new ones.
    sampler = nullptr;
    slabControlVariate = nullptr;
    slabVolume = nullptr;
    slabVolume = this->ReadSlab(slab);
    sampler = DRRStratifiedSampler::New();
    if (factor != 0)
    {
      slabControlVariate = DRRControlVariate::New();
      slabControlVariate->Build(*slabVolume, factor, threader);
    }
    sampler->Initialize(slabControlVariate ? slabControlVariate->GetResidualVolume() : *slabVolume);
  };

  // First pass: the view's mass along the curve before each slab, the whole volume's mass and the coarse volume.
  std::vector<double>        massBefore(slabs, 0.0);
  double                     viewMass = 0.0;
  uint64_t                   viewVoxels = 0;
  double                     sampledTotal = 0.0; // the mass the sampler draws from (the residual's with F), 1/mm
  unsigned int               lastSlabInView = 0;
  DRRControlVariate::Pointer controlVariate;
  for (bool declined = true; declined;)
  {
    declined = false;
    viewMass = 0.0;
    viewVoxels = 0;
    sampledTotal = 0.0;
    controlVariate = nullptr;
    if (factor != 0)
    {
      controlVariate = DRRControlVariate::New();
      controlVariate->BeginSlabs(
        { { wholeSize[0], wholeSize[1], wholeSize[2] } }, grid->GetIndexToPhysicalMatrix(), grid->GetOrigin(), factor);
    }
    for (unsigned int slab = 0; slab < slabs; ++slab)
    {
      checkAbort();
      prepareSlab(slab);
      Placement placement;
      placement.FirstPlane = firstPlaneOf(slab);
      placement.MassBefore = viewMass;
      massBefore[slab] = viewMass;
      const auto plan = planOf(placement);
      viewMass = DRRStratifiedSampler::GetMassAtEnd(*plan);
      viewVoxels += DRRStratifiedSampler::GetNumberOfVoxelsInPlan(*plan);
      lastSlabInView = DRRStratifiedSampler::GetNumberOfVoxelsInPlan(*plan) > 0 ? slab : lastSlabInView;
      placement.MassBefore = sampledTotal;
      sampledTotal = DRRStratifiedSampler::GetMassAtEnd(*sampler->MakeSlabViewPlan(nullptr, 0.0, 0.0, placement));
      if (controlVariate)
      {
        controlVariate->AddSlab(*slabControlVariate, placement.FirstPlane);
      }
      this->UpdateProgress(0.5f * static_cast<float>(slab + 1) / static_cast<float>(slabs));
    }
    if (controlVariate && m_ControlVariateFactor == AutomaticControlVariateFactor &&
        sampledTotal * grid->GetVoxelVolume() > MaximumAutomaticResidualFraction * controlVariate->GetTotalMass())
    {
      // `auto` declines as the unstreamed render does (PrepareSampling()): the pass again, without.
      itkDebugMacro("streamed control variate F " << factor << " declined");
      factor = 0;
      declined = true;
    }
  }

  // Second pass: every slab draws its window of the run's samples into the whole render's sums, or into the kept
  // points.
  const DRRSamplerTraits                  traits = sampler->GetTraits();
  const DRRPointSampler::SampleRange      run = DRRStreamedPointRender::MakeRun(settings, traits);
  std::unique_ptr<DRRStreamedPointRender> render;
  DRRPointCloud::Pointer                  cloud;
  if (keepPoints)
  {
    cloud = DRRStreamedPointRender::MakeCloud(
      settings, traits, sampler->GetMaximumWeight(), wholeSize, viewMass * grid->GetVoxelVolume(), factor != 0);
  }
  else
  {
    render = std::make_unique<DRRStreamedPointRender>(
      settings, projection, traits, sampler->GetMaximumWeight(), wholeSize, threader);
  }
  for (unsigned int slab = 0; slab < slabs; ++slab)
  {
    checkAbort();
    Placement placement;
    placement.FirstPlane = firstPlaneOf(slab);
    placement.MassBefore = massBefore[slab];
    placement.ViewMass = viewMass;
    placement.ViewVoxels = viewVoxels;
    placement.LastSlab = slab == lastSlabInView;
    if (slab <= lastSlabInView && viewVoxels > 0)
    {
      prepareSlab(slab);
      const auto                   plan = planOf(placement);
      const auto                   window = DRRStratifiedSampler::GetSampleWindow(*plan, run);
      const DRRAttenuationVolume * residual = slabControlVariate ? &slabControlVariate->GetResidualVolume() : nullptr;
      if (keepPoints)
      {
        DRRPointRenderer::Settings slabSettings = settings;
        slabSettings.SignedResidual = residual;
        DRRStreamedPointRender::DrawSlab(
          *cloud, slabSettings, *plan, *sampler, window, placement.FirstPlane, threader, nullptr);
      }
      else
      {
        render->AddSlab(*plan, *sampler, window, placement.FirstPlane, residual);
      }
    }
    this->UpdateProgress(0.5f + 0.5f * static_cast<float>(slab + 1) / static_cast<float>(slabs));
  }
  sampler = nullptr;
  slabControlVariate = nullptr;
  slabVolume = nullptr;
  if (controlVariate)
  {
    controlVariate->EndSlabs(threader);
  }
  if (keepPoints)
  {
    m_PointCloud = cloud;
    m_PointCloudStreamed = true;
    m_StreamedControlVariate = controlVariate;
    m_PointCloudTime.Modified();
    ++m_NumberOfPointCloudDraws;
    return {};
  }
  DRRPointRenderer::Result result =
    render->Finish(sampledTotal * grid->GetVoxelVolume(), viewMass * grid->GetVoxelVolume());
  if (controlVariate)
  {
    this->AddCoarseImage(*controlVariate, projection, settings, result);
  }
  return result;
}

template <typename TInputImage, typename TOutputImage>
void
PointBasedDRRImageFilter<TInputImage, TOutputImage>::VerifySettings(uint64_t samples) const
{
  if (!m_Sampler)
  {
    itkExceptionMacro("no sampler set");
  }
  if (samples < DRRPointRenderer::MinimumNumberOfSamples)
  {
    itkExceptionMacro("the number of samples must be at least 1");
  }
  if (m_NumberOfStrata == 1)
  {
    // One stratum of dependent points has no spread to measure: its standard error would assume independence.
    itkExceptionMacro("NumberOfStrata must be 0 (the sampler's choice) or 2 to 256, not 1");
  }
  if (m_ControlVariateFactor > 0 && m_ReconstructionKernel != KernelEnum::Box)
  {
    itkExceptionMacro("the control variate needs the box kernel (its coarse image is the box model's), not "
                      << m_ReconstructionKernel);
  }
  if (m_ControlVariateFactor > 0 && m_PointWeighting != WeightingEnum::Unbiased)
  {
    itkExceptionMacro("the control variate needs the unbiased point weighting (its coarse image is a line integral), "
                      "not "
                      << m_PointWeighting);
  }
  if (m_ControlVariateFactor > DRRControlVariate::MaximumFactor &&
      m_ControlVariateFactor != AutomaticControlVariateFactor)
  {
    itkExceptionMacro("ControlVariateFactor must be 0 (off), 2 to " << DRRControlVariate::MaximumFactor
                                                                    << " or AutomaticControlVariateFactor, not "
                                                                    << m_ControlVariateFactor);
  }
  if (m_ControlVariateFactor == 1)
  {
    itkExceptionMacro("ControlVariateFactor 1 would make the coarse image the exact one: use 0 (off), 2 to "
                      << DRRControlVariate::MaximumFactor << " or AutomaticControlVariateFactor");
  }
}

template <typename TInputImage, typename TOutputImage>
DRRPointRenderer::Settings
PointBasedDRRImageFilter<TInputImage, TOutputImage>::MakeSettings(uint64_t samples, unsigned int pass) const
{
  if (m_Sampler)
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
  DRRPointRenderer::Settings settings;
  settings.NumberOfSamples = samples;
  // Pass 0 is keyed by the seed itself; later passes by a SplitMix64 mix of seed and pass, so streams never repeat.
  uint64_t seed = m_Seed;
  if (pass > 0)
  {
    seed += 0x9E3779B97F4A7C15ull * pass;
    seed = (seed ^ (seed >> 30)) * 0xBF58476D1CE4E5B9ull;
    seed = (seed ^ (seed >> 27)) * 0x94D049BB133111EBull;
    seed ^= seed >> 31;
  }
  settings.Seed = seed;
  settings.Kernel = m_ReconstructionKernel;
  settings.Splat = m_Splat;
  settings.Weighting = m_PointWeighting;
  settings.NumberOfStrata = m_NumberOfStrata;
  return settings;
}

template <typename TInputImage, typename TOutputImage>
DRRPointRenderer::Result
PointBasedDRRImageFilter<TInputImage, TOutputImage>::RenderPass(uint64_t samples, unsigned int pass)
{
  const DRRPointRenderer::Settings settings = this->MakeSettings(samples, pass);
  this->UpdateProgress(0.0f);
  DRRPointRenderer::Result result;
  if (this->GetNumberOfSlabs() > 1)
  {
    result =
      m_ReusePoints && pass == 0 ? this->RenderStreamedKeptPoints(settings) : this->RenderStreamed(settings, false);
  }
  else if (m_ReusePoints && pass == 0)
  {
    result = this->RenderKeptPoints(settings);
  }
  else
  {
    this->PrepareSampling();
    const DRRAttenuationVolume & volume = this->GetSamplingVolume();
    DRRPointRenderer::Settings   signedSettings = settings;
    signedSettings.SignedResidual = m_ControlVariate ? &volume : nullptr;
    signedSettings.VoxelChannels = volume.GetVoxelChannels();
    signedSettings.NumberOfChannels = volume.GetNumberOfChannels();
    result = DRRPointRenderer::Render(
      volume, *m_Sampler, this->MakeProjection(), signedSettings, this->GetMultiThreader(), this);
    this->AddControlVariateImage(settings, result);
  }
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
  m_TotalMass = result.RoomMass;
  return result;
}

template <typename TInputImage, typename TOutputImage>
DRRPointRenderer::Result
PointBasedDRRImageFilter<TInputImage, TOutputImage>::RenderKeptPoints(DRRPointRenderer::Settings settings)
{
  this->PrepareSampling();
  const DRRAttenuationVolume & volume = this->GetSamplingVolume();
  settings.SignedResidual = m_ControlVariate ? &volume : nullptr;
  settings.VoxelChannels = volume.GetVoxelChannels();
  settings.NumberOfChannels = volume.GetNumberOfChannels();
  // The points are stale once the sampler's tables or a setting they are drawn with (samples, seed, kernel, strata)
  // are newer; the pose (transform, geometry), the splat and the weighting are not among them.
  if (!m_PointCloud || m_PointCloudStreamed ||
      std::max(m_SamplerTime.GetMTime(), m_SamplingSettingsTime.GetMTime()) > m_PointCloudTime.GetMTime())
  {
    m_PointCloud = nullptr; // free the old points before drawing new ones
    m_PointCloud = DRRPointRenderer::Draw(volume, *m_Sampler, settings, this->GetMultiThreader(), this);
    m_PointCloudTime.Modified();
    m_PointCloudStreamed = false;
    m_StreamedControlVariate = nullptr;
    ++m_NumberOfPointCloudDraws;
  }
  if (!m_PointCloudWorkspace)
  {
    m_PointCloudWorkspace = DRRPointRenderer::MakeWorkspace();
  }
  DRRPointRenderer::Result result = DRRPointRenderer::Render(
    *m_PointCloud, this->MakeProjection(), settings, this->GetMultiThreader(), this, m_PointCloudWorkspace.get());
  this->AddControlVariateImage(settings, result);
  return result;
}

template <typename TInputImage, typename TOutputImage>
bool
PointBasedDRRImageFilter<TInputImage, TOutputImage>::StreamedPointCloudIsCurrent() const
{
  // Stale once a setting the points are drawn with, the sampler, the transfer function or anything upstream of the
  // input is newer (the input's own time changes with every slab read: its source's is the one that counts).
  const TInputImage * input = this->GetInput();
  if (!m_PointCloud || !m_PointCloudStreamed || !input || !m_Sampler)
  {
    return false;
  }
  const ModifiedTimeType madeOf = std::max({ m_SamplingSettingsTime.GetMTime(),
                                             m_Sampler->GetMTime(),
                                             this->GetTransferFunction()->GetMTime(),
                                             input->GetSource() ? input->GetPipelineMTime() : input->GetMTime() });
  return madeOf <= m_PointCloudTime.GetMTime();
}

template <typename TInputImage, typename TOutputImage>
bool
PointBasedDRRImageFilter<TInputImage, TOutputImage>::ReadsSlabsAtNextUpdate() const
{
  return !(m_ReusePoints && m_RefinementSamples == 0 && this->StreamedPointCloudIsCurrent());
}

template <typename TInputImage, typename TOutputImage>
DRRPointRenderer::Result
PointBasedDRRImageFilter<TInputImage, TOutputImage>::RenderStreamedKeptPoints(
  const DRRPointRenderer::Settings & settings)
{
  if (!this->StreamedPointCloudIsCurrent())
  {
    m_PointCloud = nullptr; // free the old points before drawing new ones
    m_StreamedControlVariate = nullptr;
    this->RenderStreamed(settings, true);
  }
  if (!m_PointCloudWorkspace)
  {
    m_PointCloudWorkspace = DRRPointRenderer::MakeWorkspace();
  }
  const DRRPointProjection projection = this->MakeProjection(*this->MakeInputGrid());
  DRRPointRenderer::Result result = DRRPointRenderer::Render(
    *m_PointCloud, projection, settings, this->GetMultiThreader(), this, m_PointCloudWorkspace.get());
  if (m_StreamedControlVariate)
  {
    this->AddCoarseImage(*m_StreamedControlVariate, projection, settings, result);
  }
  return result;
}

template <typename TInputImage, typename TOutputImage>
void
PointBasedDRRImageFilter<TInputImage, TOutputImage>::GenerateData()
{
  // A render starts the passes afresh; a refinement adds one to them.
  const uint64_t refinement = std::exchange(m_RefinementSamples, uint64_t{ 0 });
  if (refinement == 0)
  {
    m_Passes.Clear();
  }
  const uint64_t samples = refinement > 0 ? refinement : m_NumberOfSamples;
  m_Passes.Add(this->RenderPass(samples, m_Passes.GetNumberOfPasses()), samples);
  const DRRPassCombination::Estimate estimate = m_Passes.Combine();
  this->WriteOutputs(estimate.LineIntegral, &estimate.StandardError);
  this->WriteChannelOutputs(estimate.ChannelLineIntegral, &estimate.ChannelCovariance);
  m_RenderTime.Modified();
  this->UpdateProgress(1.0f);
}

template <typename TInputImage, typename TOutputImage>
void
PointBasedDRRImageFilter<TInputImage, TOutputImage>::Refine(uint64_t additionalSamples)
{
  if (m_Passes.GetNumberOfPasses() == 0)
  {
    itkExceptionMacro("Refine() adds to a render: call Update() first");
  }
  // Anything upstream of the outputs newer than them (the filter's settings, geometry, transform, sampler, the input
  // or attenuation volume, modified in place or not) makes a refinement of another image.
  this->UpdateOutputInformation();
  if (this->GetOutput()->GetPipelineMTime() > m_RenderTime.GetMTime())
  {
    itkExceptionMacro("the filter, its input, geometry, transform or sampler changed since the last Update(): call "
                      "Update() before Refine()");
  }
  this->VerifySettings(additionalSamples);
  m_RefinementSamples = additionalSamples;
  this->Modified(); // the outputs are written by Update() alone
  try
  {
    this->Update();
  }
  catch (...)
  {
    m_RefinementSamples = 0;
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
  os << indent << "Sampler: " << (m_Sampler ? m_Sampler->GetNameOfClass() : "(none)") << std::endl;
  os << indent << "TotalMass (mm^2): " << m_TotalMass << std::endl;
  os << indent << "PointsOnDetector: " << this->GetPointsOnDetector() << std::endl;
  os << indent << "TotalNumberOfSamples: " << this->GetTotalNumberOfSamples() << std::endl;
  os << indent << "NumberOfPasses: " << m_Passes.GetNumberOfPasses() << std::endl;
  os << indent << "ReusePoints: " << (m_ReusePoints ? "On" : "Off") << std::endl;
  os << indent << "ExpectedNumberOfPoses: " << m_ExpectedNumberOfPoses << std::endl;
  os << indent << "PointCloud: ";
  if (m_PointCloud)
  {
    os << m_PointCloud->GetNumberOfPoints() << " points, " << m_PointCloud->GetBytesPerPoint() << " bytes per point"
       << std::endl;
  }
  else
  {
    os << "(none)" << std::endl;
  }
}
} // namespace itk

#endif
