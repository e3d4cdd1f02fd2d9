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
#ifndef itkDRRPaperHybridSampler_h
#define itkDRRPaperHybridSampler_h

#include "itkDRRCompatibility.h"
#include "itkDRRLevelSampler.h"

#include <sstream>

namespace itk
{
/** \class DRRPaperHybridSampler
 * \brief The paper's hybrid sampling (Algorithm 1), with the weights that make it unbiased.
 *
 * Each attempt picks a level l uniformly, accepts it with p(l) = mu_l / mu_max (rejection against g = 1), then plays
 * Russian roulette: if the level's size is below a random fraction of MeanSize (the mean level size), the attempt
 * survives only with probability q. A survivor draws a voxel uniformly in its level. The level's actual probability is
 * proportional to a_l = p(l) (f_l + (1 - f_l) q), f_l = min(1, size_l / MeanSize), so the exact importance weight of a
 * point is q(x) / P(x) = mu_l size_l sum(a) / (a_l sum(mu size)); the probabilities are computed for the 24-bit
 * uniforms the code compares against, so the weights are exact to the last bit of the test, not to a continuum
 * approximation. SetUseExactWeights(false) gives the paper's unweighted count, which is biased towards small,
 * dense levels.
 *
 * `paper-hybrid` in DRRSamplerFactory.
 *
 * \sa DRRLevelAliasSampler (exact importance sampling without rejection), DRRMetropolisSampler
 * \ingroup PointBasedDRR
 */
class PointBasedDRR_EXPORT DRRPaperHybridSampler : public DRRLevelSampler
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(DRRPaperHybridSampler);

  /** Standard class type aliases. */
  using Self = DRRPaperHybridSampler;
  using Superclass = DRRLevelSampler;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  /** Method for creation through the object factory. */
  itkNewMacro(Self);

  /** Run-time type information (and related methods). */
  itkOverrideGetNameOfClassMacro(DRRPaperHybridSampler);

  ///@{
  /** Russian roulette survival probability q in [0, 1]. Default 0.1. */
  itkSetClampMacro(RouletteSurvival, double, 0.0, 1.0);
  itkGetConstMacro(RouletteSurvival, double);
  ///@}

  ///@{
  /** Exact importance weights (default) or the paper's weight 1 for every point. */
  itkSetMacro(UseExactWeights, bool);
  itkGetConstMacro(UseExactWeights, bool);
  itkBooleanMacro(UseExactWeights);
  ///@}

  void
  Initialize(const DRRAttenuationVolume & volume) override;

  void
  GenerateBatch(RandomType & random, const SampleRange & range, uint64_t * voxelIndex, double * weight) const override;

  size_t
  GetTableSizeInBytes() const override;

  /** The attempts per point of the last Initialize() (the cost of the rejection and the roulette). */
  std::string
  GetStatisticsSummary() const override
  {
    std::ostringstream summary;
    summary << m_AttemptsPerPoint << " attempts per point";
    return summary.str();
  }

  /** Expected number of attempts per point (the cost of the rejection loop). */
  itkGetConstMacro(AttemptsPerPoint, double);

protected:
  DRRPaperHybridSampler() = default;
  ~DRRPaperHybridSampler() override = default;
  void
  PrintSelf(std::ostream & os, Indent indent) const override;

private:
  double              m_RouletteSurvival{ 0.1 };
  bool                m_UseExactWeights{ true };
  std::vector<double> m_Acceptance;   // p(l)
  std::vector<double> m_SizeFraction; // size_l / MeanSize
  std::vector<double> m_LevelWeight;  // exact weight of a point of level l (before the binning correction)
  double              m_AttemptsPerPoint{ 0.0 };
};
} // namespace itk

#endif
