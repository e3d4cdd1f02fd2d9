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
#ifndef itkDRRPassCombination_h
#define itkDRRPassCombination_h

#include "itkDRRPointRenderer.h"
#include "PointBasedDRRExport.h"

#include <cstdint>
#include <vector>

namespace itk
{
/** \class DRRPassCombination
 * \brief The estimate of a point-based render made of independent passes (a render and its refinements): the mean
 * of the passes weighted by the points each drew, and its standard error.
 *
 * With N_k the points pass k drew (DRRPointRenderer::Result::NumberOfSamples, as the renderer counts them) and L_k,
 * SE_k its estimate and standard error per pixel: L = sum N_k L_k / sum N_k and SE^2 = sum N_k^2 SE_k^2 / (sum N_k)^2,
 * the passes being independent; channel images and their covariances combine alike. One pass is its own estimate,
 * bit for bit.
 *
 * \sa PointBasedDRRImageFilter::Refine()
 * \ingroup PointBasedDRR
 */
class PointBasedDRR_EXPORT DRRPassCombination
{
public:
  /** The combined images: the same layout as a DRRPointRenderer::Result's. */
  struct Estimate
  {
    std::vector<double> LineIntegral;        ///< dimensionless, per pixel
    std::vector<double> StandardError;       ///< dimensionless, per pixel
    std::vector<double> ChannelLineIntegral; ///< K per pixel
    std::vector<double> ChannelCovariance;   ///< K (K + 1) / 2 per pixel (dimensionless^2)
  };

  /** Forgets every pass. */
  void
  Clear();

  /** Adds a pass (the first after Clear() starts the sums), weighted by the points it drew; a pass that drew none
   * (nothing to sample: an all-air volume, or a control variate's zero residual, whose image is exact) by the
   * requestedSamples it was asked for. Throws std::invalid_argument for a pass of another image size than the first. */
  void
  Add(const DRRPointRenderer::Result & pass, uint64_t requestedSamples);

  /** The combined estimate of the passes added. */
  Estimate
  Combine() const;

  /** The estimate's relative error: the root mean square of its standard error over the pixels, divided by the
   * image's range (max - min of the line integral): what NRMSE against the exact pixel-averaged image measures, as
   * a fraction (0.01: 1%). 0 for an image without error; infinite for a flat image with some. */
  static double
  ComputeRelativeError(const Estimate & estimate);

  /** Number of passes added. */
  unsigned int
  GetNumberOfPasses() const
  {
    return m_NumberOfPasses;
  }
  /** Points the passes are weighted by: drawn, as the renderer counts them (asked for, by passes that drew none). */
  uint64_t
  GetNumberOfSamples() const
  {
    return m_NumberOfSamples;
  }
  /** Points of the passes that landed on the detector. */
  uint64_t
  GetPointsOnDetector() const
  {
    return m_PointsOnDetector;
  }

private:
  unsigned int m_NumberOfPasses{ 0 };
  uint64_t     m_NumberOfSamples{ 0 };
  uint64_t     m_PointsOnDetector{ 0 };
  Estimate     m_FirstPass;   // one pass is its own estimate, bit for bit
  Estimate     m_WeightedSum; // sum N_k L_k, sum N_k^2 SE_k^2, sum N_k C_k, sum N_k^2 Cov_k
};
} // namespace itk

#endif
