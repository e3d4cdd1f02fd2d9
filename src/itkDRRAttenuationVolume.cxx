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
#include "itkDRRAttenuationVolume.h"
#include "vnl/vnl_det.h"

#include <algorithm>
#include <cmath>

namespace itk
{
DRRAttenuationVolume::DRRAttenuationVolume()
{
  m_IndexToPhysical.SetIdentity();
  m_Origin.Fill(0.0);
}

void
DRRAttenuationVolume::Allocate(const SizeType & size)
{
  m_Size = size;
  m_Mu.assign(static_cast<size_t>(this->GetNumberOfVoxels()), 0.0f);
  m_LevelKeys.clear();
  this->Modified();
}

void
DRRAttenuationVolume::SetIndexToPhysical(const MatrixType & indexToPhysical, const PointType & origin)
{
  m_IndexToPhysical = indexToPhysical;
  m_Origin = origin;
  this->Modified();
}

double
DRRAttenuationVolume::GetVoxelVolume() const
{
  return std::abs(vnl_det(m_IndexToPhysical.GetVnlMatrix()));
}

double
DRRAttenuationVolume::ComputeTotalMass() const
{
  // Sum per slice in double, then slices in order: fixed order, so the same bits on every run.
  double total = 0.0;
  for (float mu : m_Mu)
  {
    total += mu;
  }
  return total * this->GetVoxelVolume();
}

double
DRRAttenuationVolume::ComputeMaximumMu() const
{
  return m_Mu.empty() ? 0.0 : static_cast<double>(*std::max_element(m_Mu.begin(), m_Mu.end()));
}

void
DRRAttenuationVolume::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "Size: " << m_Size[0] << " x " << m_Size[1] << " x " << m_Size[2] << std::endl;
  os << indent << "IndexToPhysical (mm per index): " << m_IndexToPhysical << std::endl;
  os << indent << "Origin (mm): " << m_Origin << std::endl;
  os << indent << "LevelKeys: " << (m_LevelKeys.empty() ? "none" : "per voxel") << std::endl;
}
} // namespace itk
