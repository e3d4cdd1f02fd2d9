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
#ifndef itkDRRLevelSampler_h
#define itkDRRLevelSampler_h

#include "itkDRRCompatibility.h"
#include "itkDRRAttenuationLevels.h"
#include "itkDRRPointSampler.h"

namespace itk
{
/** \class DRRLevelSampler
 * \brief Base of the samplers that draw a level, then a voxel uniformly inside it (the paper's hist[l]): holds the
 * levels and builds them, with the total mass and the largest binning correction, in InitializeLevels().
 *
 * \sa DRRAttenuationLevels, DRRLevelAliasSampler, DRRMetropolisSampler, DRRPaperHybridSampler
 * \ingroup PointBasedDRR
 */
class PointBasedDRR_EXPORT DRRLevelSampler : public DRRPointSampler
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(DRRLevelSampler);

  /** Standard class type aliases. */
  using Self = DRRLevelSampler;
  using Superclass = DRRPointSampler;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  /** Run-time type information (and related methods). */
  itkOverrideGetNameOfClassMacro(DRRLevelSampler);

  ///@{
  /** Number of levels mu is binned into for volumes without levels (non-integer input), 1 .. 2^24. Default 4096. */
  itkSetClampMacro(NumberOfBins, unsigned int, 1, 1u << 24);
  itkGetConstMacro(NumberOfBins, unsigned int);
  ///@}

  /** Number of non-empty levels. */
  size_t
  GetNumberOfLevels() const
  {
    return m_Levels.GetNumberOfLevels();
  }

protected:
  DRRLevelSampler() = default;
  ~DRRLevelSampler() override = default;

  /** Builds the levels of a volume; sets the total mass and, as the largest weight, the largest binning correction. */
  void
  InitializeLevels(const DRRAttenuationVolume & volume)
  {
    m_Levels.Build(volume, m_NumberOfBins);
    m_TotalMass = m_Levels.GetTotalMuSum() * volume.GetVoxelVolume();
    m_MaximumWeight = m_Levels.GetMaximumCorrection();
  }

  /** Throws for a batch of samples from a volume with no level: all air, nothing to draw (a draw would read tables
   * that are not there). The filters render such a volume as an empty image without drawing. */
  void
  RequireLevels(const SampleRange & range) const
  {
    if (range.Count > 0 && m_Levels.GetNumberOfLevels() == 0)
    {
      itkExceptionMacro("no voxel to draw: the volume the sampler was initialized with is all air (M = 0 mm^2)");
    }
  }

  void
  PrintSelf(std::ostream & os, Indent indent) const override
  {
    Superclass::PrintSelf(os, indent);
    os << indent << "NumberOfBins: " << m_NumberOfBins << std::endl;
    os << indent << "NumberOfLevels: " << m_Levels.GetNumberOfLevels() << std::endl;
  }

  /** The levels of the volume the sampler was initialized with. */
  detail::DRRAttenuationLevels m_Levels;

private:
  unsigned int m_NumberOfBins{ 4096 };
};
} // namespace itk

#endif
