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
#ifndef itkDRRSamplerViewPlan_h
#define itkDRRSamplerViewPlan_h

#include "PointBasedDRRExport.h"

#include <array>
#include <cstdint>

namespace itk
{
/** \class DRRSamplerViewPlan
 * \brief What a sampler draws from in one render: the attenuation mass it samples and the volume's grid, plus, in a
 * culling sampler's subclass, the tables of the part in view.
 *
 * Made by DRRPointSampler::MakeViewPlan() for a view (or for the whole volume), held by the renderer for the length
 * of a render and handed to every DRRPointSampler::GenerateCoordinates() call. Immutable: a render changes neither
 * the plan nor the sampler, so renders of different views may share a sampler.
 *
 * \sa DRRPointSampler, DRRStratifiedSampler
 * \ingroup PointBasedDRR
 */
class PointBasedDRR_EXPORT DRRSamplerViewPlan
{
public:
  /** Voxels along x, y and z of the volume the sampler was initialized with. */
  using VolumeSizeType = std::array<uint64_t, 3>;

  /** A plan that draws from sampledMass (mm^2, volume frame) of a volume of volumeSize voxels. */
  DRRSamplerViewPlan(double sampledMass, const VolumeSizeType & volumeSize)
    : m_SampledMass(sampledMass), m_VolumeSize(volumeSize)
  {}
  /** Subclasses keep the tables of the part in view. */
  virtual ~DRRSamplerViewPlan() = default;

  /** The attenuation mass (mm^2, volume frame) the sampler draws from: the whole volume's (DRRPointSampler's total
   * mass), or the part inside the view. */
  double
  GetSampledMass() const
  {
    return m_SampledMass;
  }

  /** Voxels along x, y and z of the volume: linear voxel indices to (i, j, k) (x fastest). */
  const VolumeSizeType &
  GetVolumeSize() const
  {
    return m_VolumeSize;
  }

private:
  double         m_SampledMass;
  VolumeSizeType m_VolumeSize;
};
} // namespace itk

#endif
