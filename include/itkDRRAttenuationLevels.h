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
#ifndef itkDRRAttenuationLevels_h
#define itkDRRAttenuationLevels_h

#include "itkDRRAttenuationVolume.h"
#include "PointBasedDRRExport.h"

#include <memory>
#include <vector>

namespace itk
{
namespace detail
{
/** \class DRRAttenuationLevels
 * \brief The paper's hist[l]: the non-air voxels grouped by attenuation level, for the level samplers.
 *
 * A volume of levels (integer input such as HU) already holds them, one mu per level: they are used as they are,
 * not copied. Otherwise mu is binned into NumberOfBins levels, log-spaced (through the float bits of mu, which grow
 * with log2 mu piecewise linearly), and a voxel drawn uniformly from its level needs the correction weight
 * mu_v / (mean mu of the level) to stay exact. Memory: 4 bytes per non-air voxel and 28 per level.
 *
 * \sa DRRLevelSampler, DRRAttenuationVolume
 * \ingroup PointBasedDRR
 */
class PointBasedDRR_EXPORT DRRAttenuationLevels
{
public:
  /** Groups the voxels with mu > 0; numberOfBins is used only for volumes without levels. In parallel over fixed
   * blocks of voxels merged in order: the same levels, voxel order and sums on any number of threads. */
  void
  Build(const DRRAttenuationVolume & volume, unsigned int numberOfBins);

  /** Number of non-empty levels. */
  size_t
  GetNumberOfLevels() const
  {
    return m_Count.size();
  }
  /** Number of voxels of a level. */
  uint32_t
  GetCount(size_t level) const
  {
    return m_Count[level];
  }
  /** Mean mu of the voxels of a level, 1/mm (every voxel's mu, for a volume of levels). */
  double
  GetMeanMu(size_t level) const
  {
    return m_MeanMu[level];
  }
  /** Sum of mu over the level's voxels (1/mm; times the voxel volume it is the level's mass). */
  double
  GetMuSum(size_t level) const
  {
    return m_MuSum[level];
  }
  /** Sum of mu of every level, in level order. */
  const std::vector<double> &
  GetMuSums() const
  {
    return m_MuSum;
  }
  /** Sum of mu over every non-air voxel, 1/mm. */
  double
  GetTotalMuSum() const
  {
    return m_TotalMuSum;
  }
  /** Linear index of voxel number i of a level. */
  uint32_t
  GetVoxel(size_t level, uint64_t i) const
  {
    return m_Voxels[m_Start[level] + i];
  }
  /** Where GetVoxel(level, i) is stored (to prefetch it). */
  const uint32_t *
  GetVoxelAddress(size_t level, uint64_t i) const
  {
    return m_Voxels + m_Start[level] + i;
  }
  /** Exact-sampling correction of a voxel drawn uniformly from its level: 1 when levels are uniform. */
  double
  GetCorrection(uint32_t voxel, size_t level) const
  {
    return m_Uniform ? 1.0 : static_cast<double>(m_Mu[voxel]) / m_MeanMu[level];
  }
  /** Largest GetCorrection() over the voxels: 1 when levels are uniform. */
  double
  GetMaximumCorrection() const
  {
    return m_MaximumCorrection;
  }
  /** Bytes of the voxel lists (shared with a volume of levels, not copied) and the per-level tables. */
  size_t
  GetSizeInBytes() const;

private:
  void
  BuildBinned(const DRRAttenuationVolume & volume, unsigned int numberOfBins);

  const float *               m_Mu{ nullptr };
  bool                        m_Uniform{ true };
  double                      m_MaximumCorrection{ 1.0 };
  double                      m_TotalMuSum{ 0.0 };
  const uint32_t *            m_Voxels{ nullptr };   // voxels grouped by level: the volume's, or m_OwnedVoxels
  std::unique_ptr<uint32_t[]> m_OwnedVoxels;         // the binned levels' own lists
  uint64_t                    m_NumberOfVoxels{ 0 }; // entries in m_Voxels: the non-air voxels
  std::vector<uint64_t>       m_Start;               // first entry of each level in m_Voxels
  std::vector<uint32_t>       m_Count;
  std::vector<double>         m_MeanMu;
  std::vector<double>         m_MuSum;
};
} // namespace detail
} // namespace itk

#endif
