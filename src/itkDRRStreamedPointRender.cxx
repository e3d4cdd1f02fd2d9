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
#include "itkDRRStreamedPointRender.h"
#include "itkDRRDrawAndSplatChunks.h"
#include "itkDRRLabelSelection.h"
#include "itkDRRPolicies.h"
#include "itkDRRRenderPlan.h"
#include "itkDRRRenderReduction.h"
#include "itkDRRRenderWorkers.h"

#include <limits>

namespace itk
{
using namespace DRRRendering;

struct DRRStreamedPointRender::State
{
  State(const DRRPointRenderer::Settings & settings, const DRRPointProjection & projection, const Strata & strata)
    : Settings(settings), Projection(projection), RunStrata(strata)
  {}
  const DRRPointRenderer::Settings Settings;
  DRRPointProjection               Projection;
  const Strata                     RunStrata;
  DRRSamplerTraits                 Traits;
  FixedPoint                       Scales;
  DRRPointRenderer::Workspace      Workspace;
  DRRPointRenderer::Result         Result;
  MultiThreaderBase *              Threader{ nullptr };
  uint64_t                         Drawn{ 0 };
  bool                             Finished{ false };
};

DRRStreamedPointRender::DRRStreamedPointRender(const DRRPointRenderer::Settings & settings,
                                               const DRRPointProjection &         projection,
                                               const DRRSamplerTraits &           traits,
                                               double                             maximumWeight,
                                               const std::array<uint64_t, 3> &    wholeSize,
                                               MultiThreaderBase *                threader)
{
  VerifyNumberOfSamples(settings);
  if (settings.NumberOfChannels < 1 || settings.NumberOfChannels > DRRLabelSelection::MaximumNumberOfChannels)
  {
    itkGenericExceptionMacro("DRRStreamedPointRender: the number of channels must be 1 to "
                             << DRRLabelSelection::MaximumNumberOfChannels << ", not " << settings.NumberOfChannels);
  }
  if (!threader)
  {
    itkGenericExceptionMacro("DRRStreamedPointRender: no threader");
  }
  m_State = std::make_unique<State>(settings, projection, MakeStrata(traits, settings));
  State & state = *m_State;
  state.Traits = traits;
  state.Threader = threader;
  state.Result = ZeroResult(projection, settings.NumberOfChannels);
  // The box the kernel's points reach in the whole volume.
  std::array<double, 3> lower, upper;
  KernelSupport(settings.Kernel, wholeSize, lower, upper);
  state.Scales = PlanFixedPoint(static_cast<double>(state.RunStrata.GetNumberOfSamples()),
                                maximumWeight,
                                lower,
                                upper,
                                settings.Weighting == PointBasedDRREnums::PointWeighting::Unbiased,
                                state.Projection,
                                state.Result);
  PrepareWorkers(
    state.Workspace, state.RunStrata, settings.NumberOfChannels, state.Result.LineIntegral.size(), threader);
}

DRRStreamedPointRender::~DRRStreamedPointRender() = default;

DRRPointSampler::ViewPlanConstPointer
DRRStreamedPointRender::MakeSlabPlan(const DRRStratifiedSampler &                sampler,
                                     const DRRPointProjection &                  projection,
                                     const DRRPointRenderer::Settings &          settings,
                                     const DRRStratifiedSampler::SlabPlacement & placement)
{
  return sampler.MakeSlabViewPlan(&projection, KernelReach(settings.Kernel), SplatReach(settings.Splat), placement);
}

DRRPointSampler::SampleRange
DRRStreamedPointRender::MakeRun(const DRRPointRenderer::Settings & settings, const DRRSamplerTraits & traits)
{
  const Strata                 strata = MakeStrata(traits, settings);
  DRRPointSampler::SampleRange run;
  run.Seed = settings.Seed;
  run.Stratum = 0;
  run.StratumFirst = 0;
  run.StratumSize = strata.IsInterleaved() ? strata.GetNumberOfSamples() : strata.RunSize(0);
  run.NumberOfStrata = strata.IsInterleaved() ? strata.GetNumberOfStrata() : 1;
  return run;
}

DRRPointSampler::SampleRange
DRRStreamedPointRender::GetRun() const
{
  return MakeRun(m_State->Settings, m_State->Traits);
}

void
DRRStreamedPointRender::AddSlab(const DRRSamplerViewPlan &    plan,
                                const DRRPointSampler &       sampler,
                                const std::array<uint64_t, 2> window,
                                uint64_t                      firstPlane,
                                const DRRAttenuationVolume *  signedResidual,
                                const uint8_t *               voxelChannels)
{
  State & state = *m_State;
  if (state.Finished)
  {
    itkGenericExceptionMacro("DRRStreamedPointRender: AddSlab() after Finish()");
  }
  if (!state.RunStrata.IsInterleaved() && state.RunStrata.GetNumberOfStrata() > 1)
  {
    itkGenericExceptionMacro("DRRStreamedPointRender: a slab's window is a stretch of one run; the strata of "
                             << sampler.GetNameOfClass() << " are runs of their own");
  }
  if (firstPlane > std::numeric_limits<uint32_t>::max() || window[0] > window[1] ||
      window[1] > state.RunStrata.GetNumberOfSamples())
  {
    itkGenericExceptionMacro("DRRStreamedPointRender: samples [" << window[0] << ", " << window[1] << ") or plane "
                                                                 << firstPlane << " lie outside the render");
  }
  if (state.Settings.NumberOfChannels > 1 && !voxelChannels)
  {
    itkGenericExceptionMacro("DRRStreamedPointRender: a slab of " << state.Settings.NumberOfChannels
                                                                  << " channels needs the channel of its voxels");
  }
  if (window[0] == window[1])
  {
    return; // nothing of the view in this slab
  }
  const SlabWindow                   slab{ window[0], window[1], static_cast<uint32_t>(firstPlane) };
  const DRRPointRenderer::Settings & settings = state.Settings;
  DRRPolicies::Kernels::Visit(settings.Kernel, [&](auto kernel) {
    return DRRPolicies::Splats::Visit(settings.Splat, [&](auto splat) {
      const PointDrawer<decltype(kernel)>  drawer(sampler, plan, state.Traits, settings.Seed, signedResidual, slab);
      const PointSplatter<decltype(splat)> splatter(
        state.Projection, state.Scales, settings.Weighting == PointBasedDRREnums::PointWeighting::Unbiased);
      // The slab's voxel channels are its own voxels' (slab-local indices, as the drawer's), numbered as the whole's.
      const DrawAndSplatChunks<decltype(kernel), decltype(splat)> work(
        drawer, splatter, voxelChannels, settings.NumberOfChannels);
      RunChunks(work, state.RunStrata, state.Workspace, state.Threader, nullptr, drawer.GetChunks(state.RunStrata));
      return 0;
    });
  });
  state.Drawn += window[1] - window[0];
}

DRRPointCloud::Pointer
DRRStreamedPointRender::MakeCloud(const DRRPointRenderer::Settings & settings,
                                  const DRRSamplerTraits &           traits,
                                  double                             maximumWeight,
                                  const std::array<uint64_t, 3> &    wholeSize,
                                  double                             sampledMass,
                                  bool                               signedPoints)
{
  VerifyNumberOfSamples(settings);
  const Strata               strata = MakeStrata(traits, settings);
  DRRPointCloud::Description description;
  description.NumberOfRequestedSamples = settings.NumberOfSamples;
  description.NumberOfStrata = strata.GetNumberOfStrata();
  description.InterleavedStrata = strata.IsInterleaved();
  description.SampledMass = sampledMass;
  description.MaximumWeight = maximumWeight;
  description.Kernel = settings.Kernel;
  KernelSupport(settings.Kernel, wholeSize, description.SupportLower, description.SupportUpper);
  for (unsigned int a = 0; a < 3; ++a)
  {
    description.VolumeSize[a] = wholeSize[a];
  }
  description.Seed = settings.Seed;
  description.NumberOfChannels = settings.NumberOfChannels;
  auto cloud = DRRPointCloud::New();
  if (!(sampledMass > 0.0))
  {
    cloud->Allocate(0, false, false, description); // all air: no points, zero images
    return cloud;
  }
  cloud->Allocate(
    strata.GetNumberOfSamples(), maximumWeight != 1.0 || signedPoints, strata.GetNumberOfStrata() > 1, description);
  return cloud;
}

void
DRRStreamedPointRender::DrawSlab(DRRPointCloud &                    cloud,
                                 const DRRPointRenderer::Settings & settings,
                                 const DRRSamplerViewPlan &         plan,
                                 const DRRPointSampler &            sampler,
                                 const std::array<uint64_t, 2>      window,
                                 uint64_t                           firstPlane,
                                 MultiThreaderBase *                threader,
                                 ProcessObject *                    progressFilter)
{
  const DRRSamplerTraits traits = sampler.GetTraits();
  const Strata           strata = MakeStrata(traits, settings);
  if (cloud.GetNumberOfPoints() != strata.GetNumberOfSamples() || window[0] > window[1] ||
      window[1] > strata.GetNumberOfSamples() || firstPlane > std::numeric_limits<uint32_t>::max())
  {
    itkGenericExceptionMacro("DRRStreamedPointRender: samples [" << window[0] << ", " << window[1] << ") or plane "
                                                                 << firstPlane << " lie outside the cloud's run");
  }
  if (window[0] == window[1])
  {
    return;
  }
  const SlabWindow            slab{ window[0], window[1], static_cast<uint32_t>(firstPlane) };
  DRRPointRenderer::Workspace workspace;
  PrepareWorkers(workspace, strata, 1, 0, threader);
  DRRPolicies::Kernels::Visit(settings.Kernel, [&](auto kernel) {
    const PointDrawer<decltype(kernel)> drawer(sampler, plan, traits, settings.Seed, settings.SignedResidual, slab);
    const DrawChunksIntoCloud<decltype(kernel)> work(drawer, cloud, settings.VoxelChannels);
    RunChunks(work, strata, workspace, threader, progressFilter, drawer.GetChunks(strata));
    return 0;
  });
}

uint64_t
DRRStreamedPointRender::GetNumberOfSamplesDrawn() const
{
  return m_State->Drawn;
}

DRRPointRenderer::Result
DRRStreamedPointRender::Finish(double totalMass, double sampledMass)
{
  State & state = *m_State;
  if (state.Finished)
  {
    itkGenericExceptionMacro("DRRStreamedPointRender: Finish() twice");
  }
  state.Finished = true;
  state.Result.RoomMass = totalMass * state.Projection.GetRoomMassScale();
  state.Result.SampledRoomMass = sampledMass * state.Projection.GetRoomMassScale();
  if (!(state.Result.SampledRoomMass > 0.0))
  {
    // All air, or nothing in view: the exact answer is a zero image (as DRRPointRenderer::Render() returns it).
    DRRPointRenderer::Result zero = ZeroResult(state.Projection, state.Settings.NumberOfChannels);
    zero.RoomMass = state.Result.RoomMass;
    zero.SampledRoomMass = state.Result.SampledRoomMass;
    return zero;
  }
  Reduce(state.Workspace,
         state.RunStrata,
         state.Settings.NumberOfChannels,
         state.Scales,
         state.Projection.GetPixelArea(),
         state.Threader,
         state.Result);
  return std::move(state.Result);
}
} // namespace itk
