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
#ifndef itkDRRPointSampler_h
#define itkDRRPointSampler_h

#include "itkDRRAttenuationVolume.h"
#include "itkDRRPhiloxRandom.h"
#include "PointBasedDRRExport.h"

namespace itk
{
/** \class DRRPointSampler
 * \brief Policy that draws the voxels of a point-based DRR, a batch at a time.
 *
 * A sampler draws voxel v with some probability P(v) and returns, with each voxel, the weight q(v) / P(v), where
 * q(v) = mu_v * voxelVolume / M is the exact importance density: every sampler therefore estimates the same line
 * integrals (DESIGN section 2). Where inside the voxel the point goes is the reconstruction kernel's business,
 * not the sampler's.
 *
 * Batches are addressed by sample index in [0, total): a sampler may use the index (stratified samplers do) and
 * must draw its random numbers from the stream it is handed, so that results depend on the seed alone, never on
 * threads. GenerateBatch() is const and called concurrently.
 *
 * \ingroup PointBasedDRR
 */
class PointBasedDRR_EXPORT DRRPointSampler : public Object
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(DRRPointSampler);

  using Self = DRRPointSampler;
  using Superclass = Object;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  itkTypeMacro(DRRPointSampler, Object);

  /** Builds the sampling tables for a volume. The volume must outlive the sampler's use. */
  virtual void
  Initialize(const DRRAttenuationVolume & volume) = 0;

  /** Total attenuation mass M = sum mu * voxel volume (mm^2) of the volume the sampler was built for. */
  itkGetConstMacro(TotalMass, double);

  /** Largest weight GenerateBatch() can return (1 for exact importance samplers). */
  itkGetConstMacro(MaximumWeight, double);

  /** Fills voxelIndex[0 .. count) (linear index, x fastest) and weight[0 .. count) for the samples
   * firstSample .. firstSample + count - 1 of totalSamples. */
  virtual void
  GenerateBatch(DRRPhiloxRandom & random,
                uint64_t          firstSample,
                uint64_t          count,
                uint64_t          totalSamples,
                uint64_t *        voxelIndex,
                double *          weight) const = 0;

  /** Bytes held by the sampling tables. */
  virtual size_t
  GetTableSizeInBytes() const = 0;

protected:
  DRRPointSampler() = default;
  ~DRRPointSampler() override = default;
  void
  PrintSelf(std::ostream & os, Indent indent) const override
  {
    Superclass::PrintSelf(os, indent);
    os << indent << "TotalMass (mm^2): " << m_TotalMass << std::endl;
    os << indent << "MaximumWeight: " << m_MaximumWeight << std::endl;
  }

  double m_TotalMass{ 0.0 };
  double m_MaximumWeight{ 1.0 };
};
} // namespace itk

#endif
