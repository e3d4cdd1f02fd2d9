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
#ifndef itkDRRRenderWorkers_h
#define itkDRRRenderWorkers_h

// Private to the renderer (src/): what the threads of a render own (sums and batches), and how they run the chunks.

#include "itkDRRPointRenderer.h"
#include "itkDRRRenderPlan.h"

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

namespace itk
{
namespace DRRRendering
{
constexpr uint64_t     samplesPerBatch = 512;
constexpr unsigned int maximumCorners = 4; // pixels one point can reach (bilinear splat)

/** Integer fixed-point accumulators of one worker: per pixel the sum of contributions of every slot, a slot being a
 * stratum and channel, stratum * K + channel (pixel major: the slots of a pixel share a cache line), and, with a single
 * stratum, the sum of their squares per channel. */
struct Accumulator
{
  std::vector<int64_t> Sum;
  std::vector<int64_t> SumOfSquares;
  uint64_t             PointsOnDetector{ 0 };
};

/** One batch of projected points and their corners, structure of arrays in the precision TReal of the projection
 * (double: a render that draws; float: the render of a kept cloud, see DRRPointProjection::ProjectBatch()). Corner
 * major (corner c of point s at c * samplesPerBatch + s), so that every store of the preparation loop is contiguous. */
template <typename TReal>
struct SplatBatch
{
  TReal    Column[samplesPerBatch], Row[samplesPerBatch], Perspective[samplesPerBatch];
  int32_t  Index[maximumCorners * samplesPerBatch]; // into the sums: pixel * strata + stratum, or the trash slot
  int64_t  Value[maximumCorners * samplesPerBatch]; // fixed point
  int64_t  Square[maximumCorners * samplesPerBatch];
  int32_t  Stratum[samplesPerBatch];
  uint32_t Slot[samplesPerBatch]; // stratum * K + channel of every point, with K > 1 channels
};

/** One batch of drawn points, structure of arrays, so that the placement and projection loops vectorize. */
struct Batch
{
  uint64_t           Voxel[samplesPerBatch];
  uint32_t           I[samplesPerBatch + DRRPointSampler::CoordinateSlack];
  uint32_t           J[samplesPerBatch + DRRPointSampler::CoordinateSlack];
  uint32_t           K[samplesPerBatch + DRRPointSampler::CoordinateSlack];
  double             Weight[samplesPerBatch];
  uint32_t           Stratum[samplesPerBatch];
  uint32_t           JitterX[samplesPerBatch], JitterY[samplesPerBatch], JitterZ[samplesPerBatch];
  double             X[samplesPerBatch], Y[samplesPerBatch], Z[samplesPerBatch];
  SplatBatch<double> Splat; // their projection and corners
};

/** One batch of the render of a kept cloud: its points are read from the cloud. */
using CloudBatch = SplatBatch<float>;

/** What one worker owns: its sums and its batch (allocated once per render, not per chunk; only the kind of batch
 * its render uses). */
struct Worker
{
  Accumulator                 Sums;
  std::unique_ptr<Batch>      Scratch;
  std::unique_ptr<CloudBatch> CloudScratch;
};

/** Does whole chunks of work; one instantiation per policy combination, chosen once per render or draw. */
class ChunkWorkBase
{
public:
  virtual ~ChunkWorkBase() = default;
  virtual void
  Run(uint64_t chunk, const Strata & strata, Worker & worker) const = 0;
};
} // namespace DRRRendering

/** The workers of a render, kept for the next (see DRRPointRenderer::MakeWorkspace()). */
class DRRPointRenderer::Workspace
{
public:
  std::vector<DRRRendering::Worker> Workers;
  bool                              Cleared{ false }; // every sum of every worker is zero
};

namespace DRRRendering
{
/** Gives the workspace one worker per thread, whose sums (of numberOfPixels pixels times the strata and channels, or
 * none, and the trash slots) are all zero; clears only what the last render did not leave cleared. */
void
PrepareWorkers(DRRPointRenderer::Workspace & workspace,
               const Strata &                strata,
               unsigned int                  numberOfChannels,
               size_t                        numberOfPixels,
               MultiThreaderBase *           threader);

/** Runs work over the chunks [chunks[0], chunks[1]) of the strata's samples (all of them by default), with one worker
 * of the workspace per thread. */
void
RunChunks(const ChunkWorkBase &         work,
          const Strata &                strata,
          DRRPointRenderer::Workspace & workspace,
          MultiThreaderBase *           threader,
          ProcessObject *               progressFilter,
          std::array<uint64_t, 2>       chunks = { { 0, UINT64_MAX } });
} // namespace DRRRendering
} // namespace itk

#endif
