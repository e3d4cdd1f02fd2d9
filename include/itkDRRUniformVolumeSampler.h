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
#ifndef itkDRRUniformVolumeSampler_h
#define itkDRRUniformVolumeSampler_h

#include "itkDRRCompatibility.h"
#include "itkDRRPointSampler.h"

namespace itk
{
/** \class DRRUniformVolumeSampler
 * \brief The Monte Carlo volume rendering (MCVR) baseline the paper compares with: voxels drawn uniformly from the
 * whole volume box, air included, each point weighted by mu_v N_voxels / sum(mu) so that it estimates the same line
 * integrals as the importance samplers. No tables; every point reads the volume.
 *
 * `mcvr` in DRRSamplerFactory.
 *
 * \sa DRRLevelAliasSampler
 * \ingroup PointBasedDRR
 */
class PointBasedDRR_EXPORT DRRUniformVolumeSampler : public DRRPointSampler
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(DRRUniformVolumeSampler);

  /** Standard class type aliases. */
  using Self = DRRUniformVolumeSampler;
  using Superclass = DRRPointSampler;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  /** Method for creation through the object factory. */
  itkNewMacro(Self);

  /** Run-time type information (and related methods). */
  itkOverrideGetNameOfClassMacro(DRRUniformVolumeSampler);

  void
  Initialize(const DRRAttenuationVolume & volume) override;

  void
  GenerateBatch(RandomType & random, const SampleRange & range, uint64_t * voxelIndex, double * weight) const override;

  size_t
  GetTableSizeInBytes() const override
  {
    return 0;
  }

protected:
  DRRUniformVolumeSampler() = default;
  ~DRRUniformVolumeSampler() override = default;

private:
  const float * m_Mu{ nullptr };
  uint64_t      m_NumberOfVoxels{ 0 };
  double        m_WeightPerMu{ 0.0 }; // N_voxels / sum(mu), mm
};
} // namespace itk

#endif
