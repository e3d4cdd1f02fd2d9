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
#ifndef itkDRRAttenuationVolume_h
#define itkDRRAttenuationVolume_h

#include "itkObject.h"
#include "itkObjectFactory.h"
#include "itkMatrix.h"
#include "itkPoint.h"
#include "PointBasedDRRExport.h"

#include <array>
#include <cstdint>
#include <vector>

namespace itk
{
/** \class DRRAttenuationVolume
 * \brief The attenuation model the DRR filters render: mu (1/mm) on the voxel grid, with the grid's
 * index-to-physical mapping.
 *
 * Voxel (i, j, k) covers [i - 0.5, i + 0.5] x [j - 0.5, j + 0.5] x [k - 0.5, k + 0.5] in continuous index space;
 * physical = Origin + IndexToPhysical * index (IndexToPhysical = direction * diag(spacing), mm per index). The
 * filters build it once per input and transfer function; the samplers and exact projectors only read it.
 *
 * Optional level keys give every voxel an integer attenuation level (for CT: its HU value minus the minimum):
 * voxels of one level share one mu, which lets the level samplers draw exactly from mu without reading it.
 *
 * \ingroup PointBasedDRR
 */
class PointBasedDRR_EXPORT DRRAttenuationVolume : public Object
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(DRRAttenuationVolume);

  using Self = DRRAttenuationVolume;
  using Superclass = Object;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;
  using SizeType = std::array<uint64_t, 3>;
  using MatrixType = Matrix<double, 3, 3>;
  using PointType = Point<double, 3>;

  itkNewMacro(Self);
  itkTypeMacro(DRRAttenuationVolume, Object);

  /** Allocates mu for size[0] x size[1] x size[2] voxels (x fastest), filled with zero. */
  void
  Allocate(const SizeType & size);

  const SizeType &
  GetSize() const
  {
    return m_Size;
  }
  uint64_t
  GetNumberOfVoxels() const
  {
    return m_Size[0] * m_Size[1] * m_Size[2];
  }

  /** mu (1/mm), x fastest. */
  float *
  GetMuBuffer()
  {
    return m_Mu.data();
  }
  const float *
  GetMuBuffer() const
  {
    return m_Mu.data();
  }
  /** mu at an integer index, zero outside the grid (the zero padding of the tent model). */
  float
  GetMuOrZero(int64_t i, int64_t j, int64_t k) const
  {
    if (i < 0 || j < 0 || k < 0 || static_cast<uint64_t>(i) >= m_Size[0] || static_cast<uint64_t>(j) >= m_Size[1] ||
        static_cast<uint64_t>(k) >= m_Size[2])
    {
      return 0.0f;
    }
    return m_Mu[static_cast<uint64_t>(i) +
                m_Size[0] * (static_cast<uint64_t>(j) + m_Size[1] * static_cast<uint64_t>(k))];
  }

  /** Integer attenuation level of every voxel (empty when the input has none). */
  std::vector<uint32_t> &
  GetLevelKeys()
  {
    return m_LevelKeys;
  }
  const std::vector<uint32_t> &
  GetLevelKeys() const
  {
    return m_LevelKeys;
  }

  /** Index-to-physical mapping: physical = origin + matrix * continuous index (mm). */
  void
  SetIndexToPhysical(const MatrixType & indexToPhysical, const PointType & origin);
  const MatrixType &
  GetIndexToPhysicalMatrix() const
  {
    return m_IndexToPhysical;
  }
  const PointType &
  GetOrigin() const
  {
    return m_Origin;
  }

  /** Volume of one voxel, mm^3 (|det IndexToPhysical|). */
  double
  GetVoxelVolume() const;

  /** Total attenuation mass M = sum of mu * voxel volume, mm^2, accumulated in a fixed order. */
  double
  ComputeTotalMass() const;

  /** Largest mu, 1/mm. */
  double
  ComputeMaximumMu() const;

protected:
  DRRAttenuationVolume();
  ~DRRAttenuationVolume() override = default;
  void
  PrintSelf(std::ostream & os, Indent indent) const override;

private:
  SizeType              m_Size{ { 0, 0, 0 } };
  std::vector<float>    m_Mu;
  std::vector<uint32_t> m_LevelKeys;
  MatrixType            m_IndexToPhysical;
  PointType             m_Origin;
};
} // namespace itk

#endif
