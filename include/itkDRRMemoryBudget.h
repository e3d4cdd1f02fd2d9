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
#ifndef itkDRRMemoryBudget_h
#define itkDRRMemoryBudget_h

#include "itkDRRCompatibility.h"
#include "PointBasedDRRExport.h"

#include <cstdint>

namespace itk
{
/** \class DRRMemoryBudget
 * \brief How many slabs a render streams a volume in to stay within a memory budget (docs/design.md section 16).
 *
 * The one rule of the filters' MemoryBudget setting, and of pbdrr's --memory-budget, which must decide how to open
 * a CT before it has a filter.
 *
 * \sa DRRImageFilterBase::SetMemoryBudget()
 * \ingroup PointBasedDRR
 */
class PointBasedDRR_EXPORT DRRMemoryBudget
{
public:
  /** The machine's physical memory, bytes (0 if the system does not say). */
  static uint64_t
  GetPhysicalMemoryInBytes();

  /** The filters' default budget: half the physical memory, bytes. */
  static uint64_t
  GetDefaultBudgetInBytes()
  {
    return GetPhysicalMemoryInBytes() / 2;
  }

  /** Slabs that bring a render of `voxels` voxels at bytesPerVoxel within budget bytes: 1 if it fits or for no
   * budget (0), else ceil(voxels bytesPerVoxel / budget). */
  static unsigned int
  ComputeNumberOfSlabs(uint64_t voxels, double bytesPerVoxel, uint64_t budget);
};
} // namespace itk

#endif
