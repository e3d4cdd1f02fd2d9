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
#include "itkDRRRenderWorkers.h"

#include <algorithm>
#include <limits>
#include "itkDRRWorkScheduler.h"

namespace itk
{
namespace DRRRendering
{
void
PrepareWorkers(DRRPointRenderer::Workspace & workspace,
               const Strata &                strata,
               unsigned int                  numberOfChannels,
               size_t                        numberOfPixels,
               MultiThreaderBase *           threader)
{
  // Past the pixels' sums, one trash slot per stratum and channel, where corners off the detector add their 0 (see
  // PointSplatter::ProjectAndSplat()).
  const size_t slots = strata.GetNumberOfStrata() * numberOfChannels;
  const size_t sumSize = (numberOfPixels + 1) * slots;
  // The splatter addresses the sums with 32-bit indices (pixel * slots + slot): half the index width keeps the
  // scatter loops vectorized. Refuse, rather than wrap around, a detector whose sums do not fit.
  if (sumSize > static_cast<size_t>(std::numeric_limits<int32_t>::max()))
  {
    itkGenericExceptionMacro("DRRPointRenderer: " << numberOfPixels << " pixels x " << strata.GetNumberOfStrata()
                                                  << " strata x " << numberOfChannels
                                                  << " channels is more sums than a render can address (2^31); use "
                                                     "fewer pixels, strata or channels");
  }
  const size_t squareSize = strata.GetNumberOfStrata() == 1 ? sumSize : 0;
  workspace.Workers.resize(DRRWorkScheduler::GetNumberOfWorkers(threader, strata.GetNumberOfChunks()));
  for (Worker & worker : workspace.Workers)
  {
    if (!workspace.Cleared || worker.Sums.Sum.size() != sumSize)
    {
      worker.Sums.Sum.assign(sumSize, 0);
    }
    if (!workspace.Cleared || worker.Sums.SumOfSquares.size() != squareSize)
    {
      worker.Sums.SumOfSquares.assign(squareSize, 0);
    }
    worker.Sums.PointsOnDetector = 0;
  }
  workspace.Cleared = false; // until a reduction clears the sums again
}

void
RunChunks(const ChunkWorkBase &         work,
          const Strata &                strata,
          DRRPointRenderer::Workspace & workspace,
          MultiThreaderBase *           threader,
          ProcessObject *               progressFilter,
          std::array<uint64_t, 2>       chunks)
{
  std::vector<Worker> & workers = workspace.Workers;
  const uint64_t        end = std::min(chunks[1], strata.GetNumberOfChunks());
  const uint64_t        first = std::min(chunks[0], end);
  DRRWorkScheduler::Run(
    threader,
    end - first,
    [&](unsigned int worker, uint64_t chunk) { work.Run(first + chunk, strata, workers[worker]); },
    progressFilter);
}
} // namespace DRRRendering
} // namespace itk
