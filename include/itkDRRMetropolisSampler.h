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
#ifndef itkDRRMetropolisSampler_h
#define itkDRRMetropolisSampler_h

#include "itkDRRCompatibility.h"
#include "itkDRRAliasTable.h"
#include "itkDRRLevelSampler.h"

#include <sstream>

namespace itk
{
/** \class DRRMetropolisSampler
 * \brief The paper's Metropolis sampling over density levels (section 2.2.2): a Markov chain whose stationary law is
 * the level mass, then a voxel uniformly inside the level.
 *
 * Each step proposes a level uniformly and accepts it with probability min(1, mass(new) / mass(current)); a rejected
 * step repeats the current level (with a fresh voxel). One chain runs per batch of at most 512 points; it starts from
 * the stationary law itself (one alias-table draw), so every point is exactly distributed and the estimate unbiased
 * without burn-in; BurnIn steps may still be discarded first, as the paper's chains started anywhere would need. The
 * points are correlated through the chain: the renderer estimates the standard error from independent strata, which
 * includes the correlation. GetAutocorrelationTime() is the chain's integrated autocorrelation time of the sampled
 * mu (from batch means over 2^20 steps): the factor by which it needs more points than independent sampling.
 *
 * `metropolis` in DRRSamplerFactory; rendered as 16 strata by default
 * (DRRSamplerTraits::PreferredNumberOfStrata).
 *
 * \sa DRRLevelAliasSampler (the same law, drawn independently), DRRPaperHybridSampler
 * \ingroup PointBasedDRR
 */
class PointBasedDRR_EXPORT DRRMetropolisSampler : public DRRLevelSampler
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(DRRMetropolisSampler);

  /** Standard class type aliases. */
  using Self = DRRMetropolisSampler;
  using Superclass = DRRLevelSampler;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  /** Method for creation through the object factory. */
  itkNewMacro(Self);

  /** Run-time type information (and related methods). */
  itkOverrideGetNameOfClassMacro(DRRMetropolisSampler);

  ///@{
  /** Steps discarded at the start of every chain. Default 0 (the chain starts in its stationary law). */
  itkSetMacro(BurnIn, unsigned int);
  itkGetConstMacro(BurnIn, unsigned int);
  ///@}

  void
  Initialize(const DRRAttenuationVolume & volume) override;

  void
  GenerateBatch(RandomType & random, const SampleRange & range, uint64_t * voxelIndex, double * weight) const override;

  /** Dependent points (one chain per batch): the standard error comes from independent strata (16 by default). */
  DRRSamplerTraits
  GetTraits() const override
  {
    DRRSamplerTraits traits;
    traits.IndependentSamples = false;
    return traits;
  }

  /** The chain's acceptance rate and integrated autocorrelation time. */
  std::string
  GetStatisticsSummary() const override
  {
    std::ostringstream summary;
    summary << "acceptance rate " << m_AcceptanceRate << ", integrated autocorrelation time " << m_AutocorrelationTime
            << " (points needed relative to independent sampling)";
    return summary.str();
  }

  /** Bytes held by the sampling tables. */
  size_t
  GetTableSizeInBytes() const override
  {
    return m_Levels.GetSizeInBytes() + m_AliasTable.GetSizeInBytes();
  }

  /** Integrated autocorrelation time of mu along the chain (1 for independent draws). */
  itkGetConstMacro(AutocorrelationTime, double);
  /** Fraction of proposals accepted. */
  itkGetConstMacro(AcceptanceRate, double);

protected:
  DRRMetropolisSampler() = default;
  ~DRRMetropolisSampler() override = default;
  void
  PrintSelf(std::ostream & os, Indent indent) const override;

private:
  /** One chain step from level current; returns the next level. */
  uint32_t
  Step(uint32_t current, const RandomType::BlockType & bits) const
  {
    const uint32_t proposal = RandomType::ToRange32(bits[0], static_cast<uint32_t>(m_Levels.GetNumberOfLevels()));
    const double   ratio = m_Levels.GetMuSum(proposal) / m_Levels.GetMuSum(current);
    return ratio >= 1.0 || RandomType::ToUnitInterval(bits[1]) < ratio ? proposal : current;
  }
  void
  MeasureChain();

  unsigned int          m_BurnIn{ 0 };
  detail::DRRAliasTable m_AliasTable;
  double                m_AutocorrelationTime{ 1.0 };
  double                m_AcceptanceRate{ 1.0 };
};
} // namespace itk

#endif
