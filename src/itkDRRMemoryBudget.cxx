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
#include "itkDRRMemoryBudget.h"

#include <algorithm>
#include <cmath>
#include <unistd.h>

namespace itk
{
uint64_t
DRRMemoryBudget::GetPhysicalMemoryInBytes()
{
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long pageSize = sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || pageSize <= 0)
  {
    return 0;
  }
  return static_cast<uint64_t>(pages) * static_cast<uint64_t>(pageSize);
}

unsigned int
DRRMemoryBudget::ComputeNumberOfSlabs(uint64_t voxels, double bytesPerVoxel, uint64_t budget)
{
  const double bytes = static_cast<double>(voxels) * bytesPerVoxel;
  if (budget == 0 || !(bytes > static_cast<double>(budget)))
  {
    return 1;
  }
  return static_cast<unsigned int>(std::min(std::ceil(bytes / static_cast<double>(budget)), 1e9));
}
} // namespace itk
