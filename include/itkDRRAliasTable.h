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
#ifndef itkDRRAliasTable_h
#define itkDRRAliasTable_h

#include "itkDRRPhiloxRandom.h"
#include "PointBasedDRRExport.h"

#include <cstddef>
#include <vector>

namespace itk
{
namespace detail
{
/** \class DRRAliasTable
 * \brief Walker's alias method (Vose's construction): draws an index with probability proportional to its weight in
 * O(1) from 64 random bits. Probabilities are held to 2^-32.
 *
 * \sa DRRLevelAliasSampler
 * \ingroup PointBasedDRR
 */
class PointBasedDRR_EXPORT DRRAliasTable
{
public:
  /** Builds the table for non-negative weights with a positive sum. */
  void
  Build(const std::vector<double> & levelMass);

  /** An index, from two independent 32-bit random words. */
  uint32_t
  Draw(uint32_t bucketBits, uint32_t thresholdBits) const
  {
    const uint32_t bucket = DRRPhiloxRandom::ToRange32(bucketBits, static_cast<uint32_t>(m_Alias.size()));
    // A full bucket (threshold 2^32 - 1) also maps its last 2^-32 of probability to itself.
    return thresholdBits < m_Threshold[bucket] ? bucket : m_Alias[bucket];
  }

  /** Bytes held by the table: two 32-bit words per index. */
  size_t
  GetSizeInBytes() const
  {
    return m_Alias.size() * 2 * sizeof(uint32_t);
  }

private:
  std::vector<uint32_t> m_Threshold; // keep bucket b if the random word < threshold[b]
  std::vector<uint32_t> m_Alias;
};
} // namespace detail
} // namespace itk

#endif
