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
#include "itkDRRWorkScheduler.h"

#include <algorithm>
#include <atomic>

namespace itk
{
unsigned int
DRRWorkScheduler::GetNumberOfWorkers(const MultiThreaderBase * threader, uint64_t numberOfItems)
{
  return static_cast<unsigned int>(
    std::max<uint64_t>(1, std::min<uint64_t>(numberOfItems, threader->GetMaximumNumberOfThreads())));
}

void
DRRWorkScheduler::Run(MultiThreaderBase * threader,
                      uint64_t            numberOfItems,
                      const WorkType &    work,
                      ProcessObject *     progressFilter)
{
  const unsigned int workers = GetNumberOfWorkers(threader, numberOfItems);
  // Two items per worker and wave keep every worker busy; 16 to 50 waves give smooth progress at little barrier cost.
  // With few items, progress gives way: a wave holds at least two items, so never runs on one thread alone.
  const uint64_t waves = std::clamp<uint64_t>(
    std::max<uint64_t>(numberOfItems / (2 * workers), std::min<uint64_t>(16, numberOfItems / 2)), 1, 50);
  for (uint64_t wave = 0; wave < waves; ++wave)
  {
    const uint64_t        end = numberOfItems * (wave + 1) / waves;
    std::atomic<uint64_t> next{ numberOfItems * wave / waves };
    threader->ParallelizeArray(
      0,
      workers,
      [&](SizeValueType worker) {
        for (uint64_t item = next++; item < end; item = next++)
        {
          work(static_cast<unsigned int>(worker), item);
        }
      },
      nullptr);
    if (progressFilter != nullptr)
    {
      progressFilter->UpdateProgress(static_cast<float>(wave + 1) / static_cast<float>(waves));
      if (progressFilter->GetAbortGenerateData())
      {
        ProcessAborted e(__FILE__, __LINE__);
        e.SetDescription("Object " + std::string(progressFilter->GetNameOfClass()) + ": AbortGenerateDataOn");
        throw e;
      }
    }
  }
}
} // namespace itk
