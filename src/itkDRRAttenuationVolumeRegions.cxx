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
// DRRAttenuationVolume: its regions in ITK's pipeline, which let the preprocessing stage model one slab of the input
// volume at a time (docs/design.md, section 16). The rest of the class is in itkDRRAttenuationVolume.cxx.
#include "itkDRRAttenuationVolume.h"

namespace itk
{
void
DRRAttenuationVolume::SetLargestPossibleRegion(const RegionType & region)
{
  if (region != m_LargestPossibleRegion)
  {
    if (m_LargestPossibleRegion.GetNumberOfPixels() > 0)
    {
      // A region asked of another volume means nothing for this one: the next update asks for the whole volume.
      m_RequestedRegion = RegionType();
    }
    m_LargestPossibleRegion = region;
    this->Modified();
  }
}

void
DRRAttenuationVolume::SetRequestedRegion(const RegionType & region)
{
  // Not Modified(): asking for a region changes no data, as ImageBase::SetRequestedRegion().
  m_RequestedRegion = region;
}

void
DRRAttenuationVolume::SetBufferedRegion(const RegionType & region)
{
  if (region != m_BufferedRegion)
  {
    m_BufferedRegion = region;
    this->Modified();
  }
}

void
DRRAttenuationVolume::UpdateOutputInformation()
{
  Superclass::UpdateOutputInformation();
  if (m_RequestedRegion.GetNumberOfPixels() == 0)
  {
    this->SetRequestedRegionToLargestPossibleRegion();
  }
}

void
DRRAttenuationVolume::SetRequestedRegionToLargestPossibleRegion()
{
  m_RequestedRegion = m_LargestPossibleRegion;
}

bool
DRRAttenuationVolume::RequestedRegionIsOutsideOfTheBufferedRegion()
{
  return m_RequestedRegion != m_BufferedRegion;
}

bool
DRRAttenuationVolume::VerifyRequestedRegion()
{
  return m_LargestPossibleRegion.GetNumberOfPixels() == 0 || m_LargestPossibleRegion.IsInside(m_RequestedRegion);
}

void
DRRAttenuationVolume::SetRequestedRegion(const DataObject * data)
{
  if (const auto * other = dynamic_cast<const Self *>(data))
  {
    m_RequestedRegion = other->m_RequestedRegion;
  }
}

void
DRRAttenuationVolume::CopyInformation(const DataObject * data)
{
  Superclass::CopyInformation(data);
  if (const auto * other = dynamic_cast<const Self *>(data))
  {
    this->SetLargestPossibleRegion(other->m_LargestPossibleRegion);
  }
}
} // namespace itk
