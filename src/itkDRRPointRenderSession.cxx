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
#include "itkDRRPointRenderSession.h"
#include "itkDRRControlVariate.h"
#include "itkDRRStratifiedSampler.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace itk
{
DRRPointRenderSession::DRRPointRenderSession() = default;
DRRPointRenderSession::~DRRPointRenderSession() = default;

bool
DRRPointRenderSession::DrawnWith::operator==(const DrawnWith & other) const
{
  return NumberOfSamples == other.NumberOfSamples && Seed == other.Seed && Kernel == other.Kernel &&
         NumberOfStrata == other.NumberOfStrata && Sampler == other.Sampler;
}

auto
DRRPointRenderSession::MakeDrawnWith(const Request & request, uint64_t samples) -> DrawnWith
{
  DrawnWith drawn;
  drawn.NumberOfSamples = samples;
  drawn.Seed = request.Settings.Seed;
  drawn.Kernel = request.Settings.Kernel;
  drawn.NumberOfStrata = request.Settings.NumberOfStrata;
  drawn.Sampler = request.Sampler;
  return drawn;
}

DRRPointRenderer::Settings
DRRPointRenderSession::MakePassSettings(const Request &              request,
                                        uint64_t                     samples,
                                        unsigned int                 pass,
                                        const DRRAttenuationVolume * sampled)
{
  DRRPointRenderer::Settings settings = request.Settings;
  settings.NumberOfSamples = samples;
  // Pass 0 is keyed by the seed itself; later passes by a SplitMix64 mix of seed and pass, so streams never repeat.
  if (pass > 0)
  {
    uint64_t seed = settings.Seed + 0x9E3779B97F4A7C15ull * pass;
    seed = (seed ^ (seed >> 30)) * 0xBF58476D1CE4E5B9ull;
    seed = (seed ^ (seed >> 27)) * 0x94D049BB133111EBull;
    settings.Seed = seed ^ (seed >> 31);
  }
  if (sampled)
  {
    settings.SignedResidual = sampled->IsResidual() ? sampled : nullptr;
    settings.VoxelChannels = sampled->GetVoxelChannels();
    settings.NumberOfChannels = sampled->GetNumberOfChannels();
  }
  return settings;
}

uint64_t
DRRPointRenderSession::BeginPass(uint64_t renderSamples)
{
  const uint64_t refinement = std::exchange(m_RefinementSamples, uint64_t{ 0 });
  if (refinement == 0)
  {
    m_Passes.Clear(); // a render starts the passes afresh; a refinement adds one to them
  }
  return refinement > 0 ? refinement : renderSamples;
}

DRRPassCombination::Estimate
DRRPointRenderSession::AddPass(const DRRPointRenderer::Result & pass, uint64_t samples)
{
  m_Passes.Add(pass, samples);
  m_TotalMass = pass.RoomMass;
  m_PassesTime.Modified();
  DRRPassCombination::Estimate estimate = m_Passes.Combine();
  m_EstimatedError = DRRPassCombination::ComputeRelativeError(estimate);
  return estimate;
}

void
DRRPointRenderSession::RequestRefinement(uint64_t samples, ModifiedTimeType pipelineTime)
{
  if (m_Passes.GetNumberOfPasses() == 0)
  {
    itkGenericExceptionMacro("Refine() adds to a render: call Update() first");
  }
  if (pipelineTime > m_PassesTime.GetMTime())
  {
    itkGenericExceptionMacro("the filter, its input, geometry, transform or sampler changed since the last Update(): "
                             "call Update() before Refine()");
  }
  m_RefinementSamples = samples;
}

const DRRControlVariate *
DRRPointRenderSession::GetControlVariate() const
{
  return m_ControlVariate.GetPointer();
}

bool
DRRPointRenderSession::ControlVariateApplies(const Request & request)
{
  // The coarse image is the box model's line integral: other kernels and the paper's count render without (`auto`
  // resolves to off; a chosen F is refused by the filter's VerifySettings()).
  return request.Settings.Kernel == DRRPointRenderer::KernelEnum::Box &&
         request.Settings.Weighting == DRRPointRenderer::WeightingEnum::Unbiased;
}

void
DRRPointRenderSession::RefuseChosenFactorForChannels(const Request & request)
{
  // The coarse image mixes the labels of a block: channels render without a control variate.
  if (request.ControlVariateFactor != 0 && request.ControlVariateFactor != DRRControlVariate::AutomaticFactor)
  {
    itkGenericExceptionMacro("label channels are rendered without a control variate (its coarse blocks mix "
                             "labels): set ControlVariateFactor to 0 or AutomaticControlVariateFactor, not "
                             << request.ControlVariateFactor);
  }
}

unsigned int
DRRPointRenderSession::ResolveFactor(const Request &              request,
                                     const DRRAttenuationVolume & volume,
                                     const DRRPointProjection &   projection) const
{
  if (volume.GetNumberOfChannels() > 1)
  {
    RefuseChosenFactorForChannels(request);
    return 0;
  }
  if (request.ControlVariateFactor != DRRControlVariate::AutomaticFactor || !ControlVariateApplies(request))
  {
    return ControlVariateApplies(request) ? request.ControlVariateFactor : 0;
  }
  if (request.ReusePoints && m_Factor != 0 && m_Volume == &volume && m_VolumeTime == volume.GetMTime())
  {
    return m_Factor; // kept points: one split (or its decline) for every pose, chosen at the first
  }
  return DRRControlVariate::ChooseFactor(
    volume, projection, request.Settings.NumberOfSamples, request.GetPosesServed());
}

void
DRRPointRenderSession::PrepareControlVariate(const Request &              request,
                                             const DRRAttenuationVolume & volume,
                                             const DRRPointProjection &   projection,
                                             MultiThreaderBase *          threader)
{
  const unsigned int factor = this->ResolveFactor(request, volume, projection);
  if (m_Volume == &volume && m_VolumeTime == volume.GetMTime() && m_Factor == factor)
  {
    return; // made, or declined, for this volume and factor already
  }
  m_ControlVariate = nullptr; // its tables are large: free the old split before making the new one
  m_Volume = &volume;
  m_VolumeTime = volume.GetMTime();
  m_Factor = factor;
  if (factor != 0)
  {
    // The split and the sampler's tables of its residual in one pass over the volume (the tables would be stale).
    m_ControlVariate = DRRControlVariate::New();
    request.Sampler->InitializeWithControlVariate(*m_ControlVariate, volume, factor, threader);
    this->NoteTables(*request.Sampler, m_ControlVariate->GetResidualVolume());
  }
}

const DRRAttenuationVolume &
DRRPointRenderSession::GetSampledVolume() const
{
  return m_ControlVariate ? m_ControlVariate->GetResidualVolume() : *m_Volume;
}

void
DRRPointRenderSession::InitializeSampler(DRRPointSampler & sampler, const DRRAttenuationVolume & sampled)
{
  // The tables are stale once the volume sampled (the volume, or the split's residual) or the sampler changed.
  if (m_TablesOf != &sampled || m_TablesOfTime != sampled.GetMTime() || m_TablesSampler != &sampler ||
      m_TablesSamplerTime != sampler.GetMTime())
  {
    sampler.Initialize(sampled);
    this->NoteTables(sampler, sampled);
  }
}

void
DRRPointRenderSession::NoteTables(const DRRPointSampler & sampler, const DRRAttenuationVolume & sampled)
{
  m_TablesOf = &sampled;
  m_TablesOfTime = sampled.GetMTime();
  m_TablesSampler = &sampler;
  m_TablesSamplerTime = sampler.GetMTime();
  m_TablesTime.Modified();
}

void
DRRPointRenderSession::Prepare(const Request &              request,
                               const DRRAttenuationVolume & volume,
                               const DRRPointProjection &   projection,
                               MultiThreaderBase *          threader)
{
  this->PrepareControlVariate(request, volume, projection, threader);
  this->InitializeSampler(*request.Sampler, this->GetSampledVolume());
  if (request.ControlVariateFactor == DRRControlVariate::AutomaticFactor && m_ControlVariate &&
      request.Sampler->GetTotalMass() > MaximumAutomaticResidualFraction * m_ControlVariate->GetTotalMass())
  {
    // The residual holds more than the stated fraction of the mass (M_r as the sampler summed it, no pass of its
    // own): the points' error would shrink by less than the coarse image costs (or grow, above 1). `auto` renders
    // without a control variate, and remembers the F it declined for this volume (m_Factor).
    m_ControlVariate = nullptr;
    this->InitializeSampler(*request.Sampler, this->GetSampledVolume());
  }
}

void
DRRPointRenderSession::AddCoarseImage(const DRRControlVariate &          controlVariate,
                                      const Request &                    request,
                                      const DRRPointRenderer::Settings & settings,
                                      const DRRPointProjection &         projection,
                                      MultiThreaderBase *                threader,
                                      ProcessObject *                    caller,
                                      DRRPointRenderer::Result &         result)
{
  std::vector<double> pointsVariance(result.StandardError.size());
  std::transform(result.StandardError.begin(), result.StandardError.end(), pointsVariance.begin(), [](double se) {
    return se * se;
  });
  controlVariate.AddCoarseImage(projection,
                                settings.Splat,
                                request.ControlVariateRaysPerSide,
                                settings.Seed,
                                threader,
                                caller,
                                result,
                                request.ComputeStandardError ? 2u : 1u);
  // The coarse image's own part of the relative error, in the estimate's measure: what no number of points lowers.
  DRRPassCombination::Estimate coarse;
  coarse.LineIntegral = result.LineIntegral;
  coarse.StandardError.resize(pointsVariance.size());
  for (size_t p = 0; p < pointsVariance.size(); ++p)
  {
    coarse.StandardError[p] =
      std::sqrt(std::max(0.0, result.StandardError[p] * result.StandardError[p] - pointsVariance[p]));
  }
  m_CoarseImageError = DRRPassCombination::ComputeRelativeError(coarse);
}

DRRPointRenderer::Result
DRRPointRenderSession::Render(const Request &              request,
                              uint64_t                     samples,
                              const DRRAttenuationVolume & volume,
                              const DRRPointProjection &   projection,
                              MultiThreaderBase *          threader,
                              ProcessObject *              caller)
{
  m_CoarseImageError = 0.0; // until this pass's coarse image, if it has one
  const unsigned int pass = m_Passes.GetNumberOfPasses();
  if (request.ReusePoints && pass == 0)
  {
    return this->RenderKeptPoints(request, samples, volume, projection, threader, caller);
  }
  this->Prepare(request, volume, projection, threader);
  const DRRAttenuationVolume &     sampled = this->GetSampledVolume();
  const DRRPointRenderer::Settings settings = MakePassSettings(request, samples, pass, &sampled);
  DRRPointRenderer::Result         result =
    DRRPointRenderer::Render(sampled, *request.Sampler, projection, settings, threader, caller);
  if (m_ControlVariate)
  {
    this->AddCoarseImage(*m_ControlVariate, request, settings, projection, threader, caller, result);
  }
  return result;
}

DRRPointRenderer::Result
DRRPointRenderSession::RenderKeptPoints(const Request &              request,
                                        uint64_t                     samples,
                                        const DRRAttenuationVolume & volume,
                                        const DRRPointProjection &   projection,
                                        MultiThreaderBase *          threader,
                                        ProcessObject *              caller)
{
  this->Prepare(request, volume, projection, threader);
  const DRRAttenuationVolume &     sampled = this->GetSampledVolume();
  const DRRPointRenderer::Settings settings = MakePassSettings(request, samples, 0, &sampled);
  // The points are stale once the sampler's tables or a setting they are drawn with (samples, seed, kernel, strata,
  // sampler) are newer; the pose (transform, geometry), the splat and the weighting are not among them.
  const DrawnWith drawnWith = MakeDrawnWith(request, samples);
  if (!m_PointCloud || m_PointCloudStreamed || !(drawnWith == m_PointCloudDrawnWith) ||
      m_TablesTime.GetMTime() > m_PointCloudTime.GetMTime())
  {
    m_PointCloud = nullptr; // free the old points before drawing new ones
    m_StreamedControlVariate = nullptr;
    m_PointCloud = DRRPointRenderer::Draw(sampled, *request.Sampler, settings, threader, caller);
    m_PointCloudTime.Modified();
    m_PointCloudStreamed = false;
    m_PointCloudDrawnWith = drawnWith;
    ++m_NumberOfPointCloudDraws;
  }
  DRRPointRenderer::Result result = this->RenderKeptPoints(settings, projection, threader, caller);
  if (m_ControlVariate)
  {
    this->AddCoarseImage(*m_ControlVariate, request, settings, projection, threader, caller, result);
  }
  return result;
}

DRRPointRenderer::Result
DRRPointRenderSession::RenderKeptPoints(const DRRPointRenderer::Settings & settings,
                                        const DRRPointProjection &         projection,
                                        MultiThreaderBase *                threader,
                                        ProcessObject *                    caller)
{
  if (!m_Workspace)
  {
    m_Workspace = DRRPointRenderer::MakeWorkspace();
  }
  return DRRPointRenderer::Render(*m_PointCloud, projection, settings, threader, caller, m_Workspace.get());
}

bool
DRRPointRenderSession::StreamedPointsAreCurrent(const Request & request, ModifiedTimeType slabsMadeOf) const
{
  // Stale once a setting the points are drawn with, the sampler or anything the slabs are made of is newer.
  return m_PointCloud && m_PointCloudStreamed && request.Sampler &&
         MakeDrawnWith(request, request.Settings.NumberOfSamples) == m_PointCloudDrawnWith &&
         std::max(request.Sampler->GetMTime(), slabsMadeOf) <= m_PointCloudTime.GetMTime();
}

std::string
DRRPointRenderSession::WhyNotStreamable(const DRRPointSampler & sampler)
{
  if (!dynamic_cast<const DRRStratifiedSampler *>(&sampler))
  {
    return "streaming shares the points out between the slabs along the stratified sampler's curve (the unstreamed "
           "render's points); " +
           std::string(sampler.GetNameOfClass()) +
           " draws its voxels from tables of the whole volume: use the "
           "stratified sampler";
  }
  return {};
}

unsigned int
DRRPointRenderSession::ResolveStreamedFactor(const Request &                 request,
                                             const DRRAttenuationVolume &    grid,
                                             const std::array<uint64_t, 3> & wholeSize,
                                             const DRRPointProjection &      projection)
{
  if (request.ControlVariateFactor != DRRControlVariate::AutomaticFactor || !ControlVariateApplies(request))
  {
    return ControlVariateApplies(request) ? request.ControlVariateFactor : 0;
  }
  const DRRAttenuationVolume::SizeType size{ { wholeSize[0], wholeSize[1], wholeSize[2] } };
  const unsigned int                   factor = DRRControlVariate::ChooseFactor(
    size, grid.GetVoxelVolume(), projection, request.Settings.NumberOfSamples, request.GetPosesServed());
  return std::max(factor, MinimumStreamedAutomaticFactor);
}
} // namespace itk
