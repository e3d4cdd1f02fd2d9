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
#ifndef itkDRRPointDrawer_h
#define itkDRRPointDrawer_h

// Private to the renderer (src/): the drawing of points, header-only so that it is inlined into the vector clones of
// the chunk loops (itkDRRPointRenderer.cxx).

#include "itkDRRRenderWorkers.h"

#include <algorithm>
#include <array>

namespace itk
{
namespace DRRRendering
{
/** Draws the points of a chunk's samples, a batch at a time: voxel (sampler), stratum, and position inside the voxel
 * (kernel), into the batch's continuous indices X, Y, Z and weights. One instantiation per reconstruction kernel. */
template <typename TKernel>
class PointDrawer
{
public:
  /** Draws from the sampler's plan for the render (of the same sampler), with the sampler's traits; the samples of
   * window alone (a slab's, when streaming), placed in the whole volume's continuous index. */
  PointDrawer(const DRRPointSampler &      sampler,
              const DRRSamplerViewPlan &   plan,
              const DRRSamplerTraits &     traits,
              uint64_t                     seed,
              const DRRAttenuationVolume * signedResidual = nullptr,
              const SlabWindow &           window = SlabWindow())
    : m_Sampler(sampler)
    , m_Plan(plan)
    , m_ProvidesJitter(traits.ProvidesJitter)
    , m_Seed(seed)
    , m_SignedResidual(signedResidual)
    , m_Window(window)
  {}

  /** The chunks that hold the window's samples: [first, end). */
  std::array<uint64_t, 2>
  GetChunks(const Strata & strata) const
  {
    const uint64_t end = std::min(m_Window.End, strata.GetNumberOfSamples());
    const uint64_t first = std::min(m_Window.First, end);
    return { { first / DRRPointRenderer::SamplesPerChunk,
               (end + DRRPointRenderer::SamplesPerChunk - 1) / DRRPointRenderer::SamplesPerChunk } };
  }

  /** Calls consume(first, count) after each batch of the chunk's samples is placed (first: its first sample). */
  template <typename TConsume>
  inline void
  DrawChunk(uint64_t chunk, const Strata & strata, Batch & batch, TConsume && consume) const
  {
    const uint64_t end =
      std::min({ (chunk + 1) * DRRPointRenderer::SamplesPerChunk, strata.GetNumberOfSamples(), m_Window.End });
    detail::DRRPhiloxRandom      samplerStream(m_Seed, chunk, 0);
    detail::DRRPhiloxRandom      kernelStream(m_Seed, chunk, 1);
    DRRPointSampler::Cursor      cursor;
    DRRPointSampler::SampleRange range;
    range.Seed = m_Seed;
    range.NumberOfStrata = strata.IsInterleaved() ? strata.GetNumberOfStrata() : 1;
    for (range.First = std::max(chunk * DRRPointRenderer::SamplesPerChunk, m_Window.First); range.First < end;
         range.First += range.Count)
    {
      // A batch never straddles two runs.
      range.Stratum = strata.RunOfSample(range.First);
      range.StratumFirst = strata.RunFirst(range.Stratum);
      range.StratumSize = strata.RunSize(range.Stratum);
      range.Count =
        std::min({ samplesPerBatch, end - range.First, range.StratumFirst + range.StratumSize - range.First });
      this->DrawVoxels(samplerStream, range, cursor, batch);
      if (m_SignedResidual)
      {
        this->ApplySigns(range.Count, batch);
      }
      if (!strata.IsInterleaved())
      {
        std::fill(batch.Stratum, batch.Stratum + range.Count, static_cast<uint32_t>(range.Stratum));
      }
      if (!m_ProvidesJitter)
      {
        DrawJitter(kernelStream, range.Count, batch);
      }
      this->PlacePoints(range.Count, batch);
      consume(range.First, range.Count);
    }
  }

  /** The channel of the voxel of each of the count points of a batch (DRRPointRenderer::Settings::VoxelChannels). */
  template <typename TChannel>
  void
  VoxelChannels(uint64_t count, const Batch & batch, const uint8_t * voxelChannels, TChannel * channel) const
  {
    const uint64_t nx = m_Plan.GetVolumeSize()[0];
    const uint64_t nxy = nx * m_Plan.GetVolumeSize()[1];
    for (uint64_t s = 0; s < count; ++s)
    {
      channel[s] = static_cast<TChannel>(voxelChannels[batch.I[s] + nx * batch.J[s] + nxy * batch.K[s]]);
    }
  }

private:
  /** The voxels (and weights, strata, jitter) of a batch: the sampler's one coordinate path. */
  void
  DrawVoxels(detail::DRRPhiloxRandom &            stream,
             const DRRPointSampler::SampleRange & range,
             DRRPointSampler::Cursor &            cursor,
             Batch &                              batch) const
  {
    m_Sampler.GenerateCoordinates(m_Plan,
                                  stream,
                                  range,
                                  cursor,
                                  { batch.I,
                                    batch.J,
                                    batch.K,
                                    batch.Weight,
                                    batch.Stratum,
                                    batch.JitterX,
                                    batch.JitterY,
                                    batch.JitterZ,
                                    batch.Voxel });
  }

  /** A point drawn in a voxel of negative residual carries a negative weight (DRRPointRenderer::Settings). */
  void
  ApplySigns(uint64_t count, Batch & batch) const
  {
    for (uint64_t s = 0; s < count; ++s)
    {
      const bool negative = m_SignedResidual->IsNegativeResidual(batch.I[s], batch.J[s], batch.K[s]);
      batch.Weight[s] = negative ? -batch.Weight[s] : batch.Weight[s];
    }
  }

  static void
  DrawJitter(detail::DRRPhiloxRandom & stream, uint64_t count, Batch & batch)
  {
    for (uint64_t s = 0; s < count; ++s)
    {
      const detail::DRRPhiloxRandom::BlockType bits = stream.Next();
      batch.JitterX[s] = bits[0];
      batch.JitterY[s] = bits[1];
      batch.JitterZ[s] = bits[2];
    }
  }

  /** Continuous index of every point in the whole volume: its voxel centre plus the kernel's offset. */
  void
  PlacePoints(uint64_t count, Batch & batch) const
  {
    const uint32_t firstPlane = m_Window.FirstPlane;
    for (uint64_t s = 0; s < count; ++s)
    {
      batch.X[s] = static_cast<double>(static_cast<int32_t>(batch.I[s])) + TKernel::Offset(batch.JitterX[s]);
      batch.Y[s] = static_cast<double>(static_cast<int32_t>(batch.J[s])) + TKernel::Offset(batch.JitterY[s]);
      batch.Z[s] =
        static_cast<double>(static_cast<int32_t>(batch.K[s] + firstPlane)) + TKernel::Offset(batch.JitterZ[s]);
    }
  }

  const DRRPointSampler &      m_Sampler;
  const DRRSamplerViewPlan &   m_Plan;
  const bool                   m_ProvidesJitter;
  const uint64_t               m_Seed;
  const DRRAttenuationVolume * m_SignedResidual;
  const SlabWindow             m_Window;
};
} // namespace DRRRendering
} // namespace itk

#endif
