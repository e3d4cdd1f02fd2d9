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
#ifndef itkDRRStratifiedSampler_h
#define itkDRRStratifiedSampler_h

#include "itkDRRPointSampler.h"

#include <vector>

namespace itk
{
/** \class DRRStratifiedSampler
 * \brief Systematic sampling of the attenuation mass along a Morton (Z-order) curve: one random offset, then equal
 * mass steps.
 *
 * The non-air voxels are laid out in Morton order (8 x 8 x 8 bricks in Morton order, Morton order inside a brick) and
 * their mass is accumulated along it. The n points of a stratum sit at the masses (U + i) / n of the total, i = 0 ..
 * n - 1, with one uniform offset U per stratum: every voxel receives its expected count N mass_v / M to within one
 * point, so the count noise that dominates i.i.d. sampling is gone, and points spread evenly through space because the
 * curve keeps neighbours together. The estimate stays unbiased (each point is uniform over the mass for a uniform U)
 * and every weight is 1. Points are not independent: the renderer draws 4 strata (by default) with independent
 * offsets and estimates the standard error from their spread. Beyond the paper, whose future work named low-discrepancy
 * sampling. Inside the voxel, points follow a randomly shifted R2 low-discrepancy sequence (GenerateJitter()).
 * Tables: 4 bytes of index and 8 of cumulative mass per non-air voxel.
 *
 * \ingroup PointBasedDRR
 */
class PointBasedDRR_EXPORT DRRStratifiedSampler : public DRRPointSampler
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(DRRStratifiedSampler);

  using Self = DRRStratifiedSampler;
  using Superclass = DRRPointSampler;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  itkNewMacro(Self);
  itkTypeMacro(DRRStratifiedSampler, DRRPointSampler);

  void
  Initialize(const DRRAttenuationVolume & volume) override;

  void
  GenerateBatch(DRRPhiloxRandom &   random,
                const SampleRange & range,
                uint64_t *          voxelIndex,
                double *            weight) const override;

  bool
  HasIndependentSamples() const override
  {
    return false;
  }

  /** 4: on the LIDC chest at 10^8 points, 1.62x less error than i.i.d. sampling, against 1.38x with 8 or 16 strata
   * (each stratum is a systematic sample of N / R points; their independent boundary errors add up). */
  unsigned int
  GetPreferredNumberOfStrata() const override
  {
    return 4;
  }

  /** Low-discrepancy jitter: the R2 sequence (steps of 1 / plastic number^k per axis) with a random shift per
   * stratum, so each point is uniform in its voxel and consecutive points, which share voxels, spread evenly. */
  bool
  ProvidesJitter() const override
  {
    return true;
  }
  void
  GenerateJitter(const SampleRange & range, uint32_t * bits) const override;

  size_t
  GetTableSizeInBytes() const override
  {
    return m_Order.size() * sizeof(uint32_t) + m_Cumulative.size() * sizeof(double);
  }

protected:
  DRRStratifiedSampler() = default;
  ~DRRStratifiedSampler() override = default;

private:
  std::vector<uint32_t> m_Order;      // non-air voxels in Morton order
  std::vector<double>   m_Cumulative; // mu summed along the order, up to and including each voxel (1/mm)
};
} // namespace itk

#endif
