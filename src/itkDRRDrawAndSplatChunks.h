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
#ifndef itkDRRDrawAndSplatChunks_h
#define itkDRRDrawAndSplatChunks_h

// Private to the renderer (src/): the work of a render that draws its points as it goes, and of a draw into a cloud,
// whole (DRRPointRenderer) or a slab at a time (DRRStreamedPointRender).

#include "itkDRRCompilerBuiltins.h"
#include "itkDRRPointDrawer.h"
#include "itkDRRPointSplatter.h"
#include "itkDRRPointCloud.h"

#include <algorithm>

namespace itk
{
namespace DRRRendering
{
/** A render that draws its points as it goes (nothing kept). */
template <typename TKernel, typename TSplat>
class DrawAndSplatChunks : public ChunkWorkBase
{
public:
  DrawAndSplatChunks(const PointDrawer<TKernel> &  drawer,
                     const PointSplatter<TSplat> & splatter,
                     const uint8_t *               voxelChannels,
                     unsigned int                  numberOfChannels)
    : m_Drawer(drawer), m_Splatter(splatter), m_VoxelChannels(voxelChannels), m_NumberOfChannels(numberOfChannels)
  {}
  void
  Run(uint64_t chunk, const Strata & strata, Worker & worker) const override
  {
    this->RunChunk(chunk, strata, worker);
  }

private:
  PointBasedDRR_VECTOR_CLONES void
  RunChunk(uint64_t chunk, const Strata & strata, Worker & worker) const
  {
    if (!worker.Scratch)
    {
      worker.Scratch.reset(new Batch);
    }
    Batch &        batch = *worker.Scratch;
    const uint32_t channels = m_NumberOfChannels;
    m_Drawer.DrawChunk(chunk, strata, batch, [&](uint64_t, uint64_t count) {
      const uint32_t * slot = batch.Stratum;
      if (channels > 1)
      {
        m_Drawer.VoxelChannels(count, batch, m_VoxelChannels, batch.Splat.Slot);
        for (uint64_t s = 0; s < count; ++s)
        {
          batch.Splat.Slot[s] += batch.Stratum[s] * channels;
        }
        slot = batch.Splat.Slot;
      }
      m_Splatter.ProjectAndSplat(count,
                                 batch.X,
                                 batch.Y,
                                 batch.Z,
                                 batch.Weight,
                                 slot,
                                 batch.Splat,
                                 strata.GetNumberOfStrata() * channels,
                                 worker.Sums);
    });
  }

  const PointDrawer<TKernel> &  m_Drawer;
  const PointSplatter<TSplat> & m_Splatter;
  const uint8_t *               m_VoxelChannels;
  const unsigned int            m_NumberOfChannels;
};

/** Draws points into a cloud (no sums). */
template <typename TKernel>
class DrawChunksIntoCloud : public ChunkWorkBase
{
public:
  DrawChunksIntoCloud(const PointDrawer<TKernel> & drawer, DRRPointCloud & cloud, const uint8_t * voxelChannels)
    : m_Drawer(drawer), m_Cloud(cloud), m_VoxelChannels(voxelChannels)
  {}
  void
  Run(uint64_t chunk, const Strata & strata, Worker & worker) const override
  {
    if (!worker.Scratch)
    {
      worker.Scratch.reset(new Batch);
    }
    Batch &   batch = *worker.Scratch;
    float *   x = m_Cloud.GetX();
    float *   y = m_Cloud.GetY();
    float *   z = m_Cloud.GetZ();
    float *   weights = m_Cloud.GetWeights();
    uint8_t * stratum = m_Cloud.GetStrata();
    uint8_t * channel = m_Cloud.GetChannels();
    m_Drawer.DrawChunk(chunk, strata, batch, [&](uint64_t first, uint64_t count) {
      for (uint64_t s = 0; s < count; ++s)
      {
        x[first + s] = static_cast<float>(batch.X[s]);
        y[first + s] = static_cast<float>(batch.Y[s]);
        z[first + s] = static_cast<float>(batch.Z[s]);
      }
      if (weights)
      {
        std::transform(batch.Weight, batch.Weight + count, weights + first, [](double w) { return float(w); });
      }
      if (stratum)
      {
        std::transform(batch.Stratum, batch.Stratum + count, stratum + first, [](uint32_t r) { return uint8_t(r); });
      }
      if (channel)
      {
        m_Drawer.VoxelChannels(count, batch, m_VoxelChannels, channel + first);
      }
    });
  }

private:
  const PointDrawer<TKernel> & m_Drawer;
  DRRPointCloud &              m_Cloud;
  const uint8_t *              m_VoxelChannels;
};

} // namespace DRRRendering
} // namespace itk

#endif
