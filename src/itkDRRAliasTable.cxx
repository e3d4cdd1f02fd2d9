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
#include "itkDRRAliasTable.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace itk
{
namespace detail
{
void
DRRAliasTable::Build(const std::vector<double> & levelMass)
{
  // Vose's alias method. Bucket b keeps itself with probability threshold[b] / 2^32, else goes to alias[b].
  const size_t numberOfLevels = levelMass.size();
  m_Threshold.assign(numberOfLevels, std::numeric_limits<uint32_t>::max());
  m_Alias.resize(numberOfLevels);
  if (numberOfLevels == 0)
  {
    return;
  }
  double total = 0.0;
  for (double m : levelMass)
  {
    total += m;
  }
  std::vector<double> scaled(numberOfLevels);
  std::vector<size_t> small;
  std::vector<size_t> large;
  for (size_t l = 0; l < numberOfLevels; ++l)
  {
    scaled[l] = levelMass[l] / total * static_cast<double>(numberOfLevels);
    m_Alias[l] = static_cast<uint32_t>(l);
    (scaled[l] < 1.0 ? small : large).push_back(l);
  }
  while (!small.empty() && !large.empty())
  {
    const size_t s = small.back();
    small.pop_back();
    const size_t g = large.back();
    m_Threshold[s] = static_cast<uint32_t>(std::min(4294967295.0, std::floor(scaled[s] * 4294967296.0 + 0.5)));
    m_Alias[s] = static_cast<uint32_t>(g);
    scaled[g] = (scaled[g] + scaled[s]) - 1.0;
    if (scaled[g] < 1.0)
    {
      large.pop_back();
      small.push_back(g);
    }
  }
  // Whatever is left has probability 1 up to rounding: keep itself always.
  for (size_t l : small)
  {
    m_Threshold[l] = std::numeric_limits<uint32_t>::max();
    m_Alias[l] = static_cast<uint32_t>(l);
  }
  for (size_t l : large)
  {
    m_Threshold[l] = std::numeric_limits<uint32_t>::max();
    m_Alias[l] = static_cast<uint32_t>(l);
  }
}

} // namespace detail
} // namespace itk
