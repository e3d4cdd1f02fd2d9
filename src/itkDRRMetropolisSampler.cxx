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
#include "itkDRRMetropolisSampler.h"

#include <cmath>
#include <vector>

namespace itk
{
void
DRRMetropolisSampler::Initialize(const DRRAttenuationVolume & volume)
{
  this->InitializeLevels(volume);
  m_AliasTable.Build(m_Levels.GetMuSums());
  this->MeasureChain();
  this->Modified();
}

void
DRRMetropolisSampler::MeasureChain()
{
  // Batch means: with B batches of b steps of f = mean mu of the level, tau = b Var(batch means) / Var(f). The
  // 2^20 steps run as 16 independent chains, each started in the stationary law (so no burn-in), in parallel; their
  // sums are merged in chain order, the same bits on any number of threads.
  m_AutocorrelationTime = 1.0;
  m_AcceptanceRate = 1.0;
  if (m_Levels.GetNumberOfLevels() < 2)
  {
    return;
  }
  constexpr uint64_t numberOfChains = 16;
  constexpr uint64_t batchesPerChain = 16;
  constexpr uint64_t batchLength = 4096;
  struct ChainSums
  {
    double   Sum{ 0.0 };
    double   SumOfSquares{ 0.0 };
    double   BatchMeanSum{ 0.0 };
    double   BatchMeanSquares{ 0.0 };
    uint64_t Accepted{ 0 };
  };
  std::vector<ChainSums> chains(numberOfChains);
  DRRAttenuationVolume::ParallelizeBlocks(
    numberOfChains,
    [&](uint64_t c) {
      ChainSums &             chain = chains[c];
      detail::DRRPhiloxRandom random(0, ~uint64_t{ 0 } - c, 3);
      const auto              start = random.Next();
      uint32_t                level = m_AliasTable.Draw(start[0], start[1]);
      for (uint64_t b = 0; b < batchesPerChain; ++b)
      {
        double batchSum = 0.0;
        for (uint64_t i = 0; i < batchLength; ++i)
        {
          const uint32_t next = this->Step(level, random.Next());
          chain.Accepted += next != level ? 1 : 0;
          level = next;
          const double f = m_Levels.GetMeanMu(level);
          batchSum += f;
          chain.Sum += f;
          chain.SumOfSquares += f * f;
        }
        const double batchMean = batchSum / batchLength;
        chain.BatchMeanSum += batchMean;
        chain.BatchMeanSquares += batchMean * batchMean;
      }
    },
    nullptr);
  ChainSums total;
  for (const ChainSums & chain : chains)
  {
    total.Sum += chain.Sum;
    total.SumOfSquares += chain.SumOfSquares;
    total.BatchMeanSum += chain.BatchMeanSum;
    total.BatchMeanSquares += chain.BatchMeanSquares;
    total.Accepted += chain.Accepted;
  }
  const double n = static_cast<double>(numberOfChains * batchesPerChain * batchLength);
  const double batches = static_cast<double>(numberOfChains * batchesPerChain);
  const double variance = (total.SumOfSquares - total.Sum * total.Sum / n) / (n - 1.0);
  const double batchVariance =
    (total.BatchMeanSquares - total.BatchMeanSum * total.BatchMeanSum / batches) / (batches - 1.0);
  m_AutocorrelationTime = variance > 0.0 ? batchLength * batchVariance / variance : 1.0;
  m_AcceptanceRate = static_cast<double>(total.Accepted) / n;
}

void
DRRMetropolisSampler::GenerateBatch(detail::DRRPhiloxRandom & random,
                                    const SampleRange &       range,
                                    uint64_t *                voxelIndex,
                                    double *                  weight) const
{
  if (m_Levels.GetNumberOfLevels() == 0)
  {
    return;
  }
  const detail::DRRPhiloxRandom::BlockType start = random.Next();
  uint32_t                                 level = m_AliasTable.Draw(start[0], start[1]);
  for (unsigned int i = 0; i < m_BurnIn; ++i)
  {
    level = this->Step(level, random.Next());
  }
  for (uint64_t i = 0; i < range.Count; ++i)
  {
    const detail::DRRPhiloxRandom::BlockType bits = random.Next();
    level = this->Step(level, bits);
    const uint32_t voxel =
      m_Levels.GetVoxel(level, detail::DRRPhiloxRandom::ToRange(bits[2], bits[3], m_Levels.GetCount(level)));
    voxelIndex[i] = voxel;
    weight[i] = m_Levels.GetCorrection(voxel, level);
  }
}

void
DRRMetropolisSampler::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "BurnIn: " << m_BurnIn << std::endl;
  os << indent << "AcceptanceRate: " << m_AcceptanceRate << std::endl;
  os << indent << "AutocorrelationTime: " << m_AutocorrelationTime << std::endl;
}
} // namespace itk
