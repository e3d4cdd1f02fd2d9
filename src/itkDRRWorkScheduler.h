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
#ifndef itkDRRWorkScheduler_h
#define itkDRRWorkScheduler_h

#include "itkMultiThreaderBase.h"
#include "itkProcessObject.h"
#include "PointBasedDRRExport.h"

#include <functional>

namespace itk
{
/** \class DRRWorkScheduler
 * \brief Runs numbered work items on ITK's threads, reporting progress and honouring abort.
 *
 * Items are handed out dynamically to one worker per thread, in 16 to 50 waves of at least two items each (fewer
 * waves for fewer items). Between waves the calling thread (the pipeline's) updates the filter's progress, which is
 * what makes ProgressEvent observers fire during the work (ITK invokes them only from that thread), and throws
 * ProcessAborted if AbortGenerateData is set. A worker index in [0, GetNumberOfWorkers()) lets each worker own an
 * accumulator.
 *
 * \ingroup PointBasedDRR
 */
class PointBasedDRR_EXPORT DRRWorkScheduler
{
public:
  /** A work item: called with the index of the worker that runs it and the item's number. */
  using WorkType = std::function<void(unsigned int worker, uint64_t item)>;

  /** Number of workers Run() uses for this many items. */
  static unsigned int
  GetNumberOfWorkers(const MultiThreaderBase * threader, uint64_t numberOfItems);

  /** Calls work(worker, item) once for every item in [0, numberOfItems) on the threads of threader (not null).
   * progressFilter may be null. */
  static void
  Run(MultiThreaderBase * threader, uint64_t numberOfItems, const WorkType & work, ProcessObject * progressFilter);
};
} // namespace itk

#endif
