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
#include "itkDRRPaperHybridSampler.h"

#include <algorithm>
#include <cmath>

namespace itk
{
namespace
{
/** P(U <= x) for U = k / 2^24, k uniform in [0, 2^24): the probability of the comparisons below, exactly. */
double
ProbabilityUniformAtMost(double x)
{
  if (x < 0.0)
  {
    return 0.0;
  }
  if (x >= 1.0)
  {
    return 1.0;
  }
  return (std::floor(x * 16777216.0) + 1.0) / 16777216.0;
}
} // namespace

void
DRRPaperHybridSampler::Initialize(const DRRAttenuationVolume & volume)
{
  this->InitializeLevels(volume);
  const size_t levels = m_Levels.GetNumberOfLevels();
  m_Acceptance.assign(levels, 0.0);
  m_SizeFraction.assign(levels, 0.0);
  m_LevelWeight.assign(levels, 0.0);
  m_MaximumWeight = 1.0;
  m_AttemptsPerPoint = 0.0;
  if (levels == 0)
  {
    this->Modified();
    return;
  }
  double largestMu = 0.0;
  double meanSize = 0.0;
  for (size_t l = 0; l < levels; ++l)
  {
    largestMu = std::max(largestMu, m_Levels.GetMeanMu(l));
    meanSize += m_Levels.GetCount(l);
  }
  meanSize /= static_cast<double>(levels);

  // a_l: probability that an attempt ends with level l, times the number of levels.
  const double        survival = ProbabilityUniformAtMost(m_RouletteSurvival);
  std::vector<double> levelProbability(levels);
  double              sum = 0.0;
  for (size_t l = 0; l < levels; ++l)
  {
    m_Acceptance[l] = m_Levels.GetMeanMu(l) / largestMu;
    m_SizeFraction[l] = m_Levels.GetCount(l) / meanSize;
    // The roulette is played when size < U MeanSize, i.e. U > size / MeanSize.
    const double notPlayed = ProbabilityUniformAtMost(m_SizeFraction[l]);
    levelProbability[l] = ProbabilityUniformAtMost(m_Acceptance[l]) * (notPlayed + (1.0 - notPlayed) * survival);
    sum += levelProbability[l];
  }
  m_AttemptsPerPoint = static_cast<double>(levels) / sum;
  for (size_t l = 0; l < levels; ++l)
  {
    // q(v) / P(v) = (mu_l / sum mu) / (a_l / (sum a size_l))
    m_LevelWeight[l] =
      levelProbability[l] > 0.0 ? m_Levels.GetMuSum(l) * sum / (levelProbability[l] * m_Levels.GetTotalMuSum()) : 0.0;
    m_MaximumWeight = std::max(m_MaximumWeight, m_LevelWeight[l]);
  }
  m_MaximumWeight *= m_Levels.GetMaximumCorrection();
  this->Modified();
}

void
DRRPaperHybridSampler::GenerateBatch(detail::DRRPhiloxRandom & random,
                                     const SampleRange &       range,
                                     uint64_t *                voxelIndex,
                                     double *                  weight) const
{
  this->RequireLevels(range);
  const uint64_t count = range.Count;
  const uint32_t levels = static_cast<uint32_t>(m_Levels.GetNumberOfLevels());
  for (uint64_t i = 0; i < count; ++i)
  {
    uint32_t level = 0;
    for (;;)
    {
      const detail::DRRPhiloxRandom::BlockType bits = random.Next();
      level = detail::DRRPhiloxRandom::ToRange32(bits[0], levels);
      if (!(detail::DRRPhiloxRandom::ToUnitInterval(bits[1]) <= m_Acceptance[level]))
      {
        continue; // rejected against p(l)
      }
      if (!(detail::DRRPhiloxRandom::ToUnitInterval(bits[2]) <= m_SizeFraction[level]) &&
          !(detail::DRRPhiloxRandom::ToUnitInterval(bits[3]) <= m_RouletteSurvival))
      {
        continue; // a small level lost the roulette
      }
      break;
    }
    const detail::DRRPhiloxRandom::BlockType bits = random.Next();
    const uint32_t                           voxel =
      m_Levels.GetVoxel(level, detail::DRRPhiloxRandom::ToRange(bits[0], bits[1], m_Levels.GetCount(level)));
    voxelIndex[i] = voxel;
    weight[i] = m_UseExactWeights ? m_LevelWeight[level] * m_Levels.GetCorrection(voxel, level) : 1.0;
  }
}

size_t
DRRPaperHybridSampler::GetTableSizeInBytes() const
{
  return m_Levels.GetSizeInBytes() + m_Acceptance.size() * 3 * sizeof(double);
}

void
DRRPaperHybridSampler::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "RouletteSurvival: " << m_RouletteSurvival << std::endl;
  os << indent << "UseExactWeights: " << m_UseExactWeights << std::endl;
  os << indent << "AttemptsPerPoint: " << m_AttemptsPerPoint << std::endl;
}
} // namespace itk
