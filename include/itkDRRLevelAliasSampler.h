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
#ifndef itkDRRLevelAliasSampler_h
#define itkDRRLevelAliasSampler_h

#include "itkDRRCompatibility.h"
#include "itkDRRAliasTable.h"
#include "itkDRRLevelSampler.h"

#include <vector>

namespace itk
{
/** \class DRRLevelAliasSampler
 * \brief Exact importance sampling by attenuation level: a level from an alias table with probability proportional
 * to its mass (mu_l * count_l), then a voxel uniformly inside it.
 *
 * This is the paper's per-level voxel lists (hist[l]) with Walker's alias method in place of its rejection loop:
 * O(1) per sample, no rejection, 4 bytes per non-air voxel plus a few per level. With a volume of levels (integer
 * input, e.g. HU), the lists are the volume's own, all voxels of a level share one mu and every weight is exactly 1.
 * Without (non-integer input), mu is binned into levels and each sample carries the exact correction
 * mu_v / mean mu of its level, so the estimate stays unbiased; the volume is then read at sample time.
 *
 * The default sampler of PointBasedDRRImageFilter (`level-alias` in DRRSamplerFactory).
 *
 * \sa DRRAliasTable, DRRAttenuationLevels, DRRStratifiedSampler
 * \ingroup PointBasedDRR
 */
class PointBasedDRR_EXPORT DRRLevelAliasSampler : public DRRLevelSampler
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(DRRLevelAliasSampler);

  /** Standard class type aliases. */
  using Self = DRRLevelAliasSampler;
  using Superclass = DRRLevelSampler;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  /** Method for creation through the object factory. */
  itkNewMacro(Self);

  /** Run-time type information (and related methods). */
  itkOverrideGetNameOfClassMacro(DRRLevelAliasSampler);

  void
  Initialize(const DRRAttenuationVolume & volume) override;

  void
  GenerateBatch(RandomType & random, const SampleRange & range, uint64_t * voxelIndex, double * weight) const override;

  size_t
  GetTableSizeInBytes() const override;

protected:
  DRRLevelAliasSampler() = default;
  ~DRRLevelAliasSampler() override = default;
  void
  PrintSelf(std::ostream & os, Indent indent) const override;

private:
  detail::DRRAliasTable m_AliasTable;
};
} // namespace itk

#endif
