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
#include "itkDRRPointCloud.h"

namespace itk
{
void
DRRPointCloud::Allocate(uint64_t numberOfPoints, bool withWeights, bool withStrata, const Description & description)
{
  if (withStrata && description.NumberOfStrata > 256)
  {
    itkExceptionMacro("a point cloud holds at most 256 strata, not " << description.NumberOfStrata);
  }
  if (description.NumberOfChannels == 0 || description.NumberOfChannels > 256)
  {
    itkExceptionMacro("a point cloud holds 1 to 256 channels, not " << description.NumberOfChannels);
  }
  m_X.resize(numberOfPoints);
  m_Y.resize(numberOfPoints);
  m_Z.resize(numberOfPoints);
  m_Weight.resize(withWeights ? numberOfPoints : 0);
  m_Stratum.resize(withStrata ? numberOfPoints : 0);
  m_Channel.resize(description.NumberOfChannels > 1 ? numberOfPoints : 0);
  m_Description = description;
  this->Modified();
}

size_t
DRRPointCloud::GetSizeInBytes() const
{
  return (m_X.size() + m_Y.size() + m_Z.size() + m_Weight.size()) * sizeof(float) + m_Stratum.size() + m_Channel.size();
}

double
DRRPointCloud::GetBytesPerPoint() const
{
  return m_X.empty() ? 0.0 : static_cast<double>(this->GetSizeInBytes()) / static_cast<double>(m_X.size());
}

void
DRRPointCloud::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "NumberOfPoints: " << this->GetNumberOfPoints() << std::endl;
  os << indent << "BytesPerPoint: " << this->GetBytesPerPoint() << std::endl;
  os << indent << "NumberOfStrata: " << m_Description.NumberOfStrata << std::endl;
  os << indent << "NumberOfChannels: " << m_Description.NumberOfChannels << std::endl;
  os << indent << "SampledMass (mm^2): " << m_Description.SampledMass << std::endl;
  os << indent << "Kernel: " << m_Description.Kernel << std::endl;
  os << indent << "Seed: " << m_Description.Seed << std::endl;
}
} // namespace itk
