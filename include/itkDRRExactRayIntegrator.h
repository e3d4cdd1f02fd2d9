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
#ifndef itkDRRExactRayIntegrator_h
#define itkDRRExactRayIntegrator_h

#include "itkDRRPointProjection.h"
#include "itkMultiThreaderBase.h"
#include "itkProcessObject.h"
#include "PointBasedDRRExport.h"

#include <vector>

namespace itk
{
/** \class DRRExactRayIntegrator
 * \brief Exact line integrals through the two voxel models, and the pixel-averaged projection built from them.
 *
 * - Box (piecewise-constant) model: Siddon's method, a voxel-by-voxel traversal of [-0.5, n - 0.5]^3 in continuous
 *   index space, summing mu times the length in each voxel. The exit voxel and the outer half-voxel shell are kept.
 * - Tent (trilinear) model: the trilinear interpolant of the volume padded with one layer of zero voxels, whose
 *   support is [-1, n]^3. The ray is cut at the dual grid (the cells between voxel centres); inside a cell the
 *   interpolant is a cubic polynomial of the ray parameter, so 2-point Gauss-Legendre per segment is exact.
 *
 * A pixel value is the average of k x k rays through the centres of a regular k x k subdivision of the pixel (the
 * midpoint rule for the pixel-area average; exact in the limit, and for k = 1 the classic one ray per pixel).
 *
 * \sa ExactDRRImageFilter
 * \ingroup PointBasedDRR
 */
class PointBasedDRR_EXPORT DRRExactRayIntegrator
{
public:
  /** Box (Siddon) or Tent (trilinear) voxel model. */
  using KernelEnum = PointBasedDRREnums::ReconstructionKernel;

  /** Integrates through the box or tent model of a volume, which must outlive the integrator (it is not copied); throws
   * ExceptionObject for a kernel whose model has no exact projector here (DRRBoxKernel::ExactReference). */
  DRRExactRayIntegrator(const DRRAttenuationVolume & volume, KernelEnum kernel);

  /** Integral of mu over the parameter t in [0, 1] of the segment p0 -> p1 (continuous index coordinates): multiply
   * by the segment's length in mm to get the line integral. */
  double
  IntegrateSegment(const double p0[3], const double p1[3]) const;

  /** Line integral (dimensionless) along one ray through the detector point (column, row), fractional allowed. */
  double
  IntegrateRay(const DRRPointProjection & projection, double column, double row) const;

  /** The projection image (cols x rows, columns fastest; dimensionless line integrals): the average of raysPerSide^2
   * rays per pixel, on the threads of threader (not null), reporting progress to progressFilter (may be null), which
   * is also checked for abort. */
  std::vector<double>
  RenderProjection(const DRRPointProjection & projection,
                   unsigned int               raysPerSide,
                   MultiThreaderBase *        threader,
                   ProcessObject *            progressFilter) const;

private:
  double
  Trilinear(const int64_t corner[3], const double fraction[3]) const;

  const DRRAttenuationVolume & m_Volume;
  bool                         m_Siddon;    // the box model's Siddon traversal, or else the trilinear one
  double                       m_GridStart; // continuous index of the first grid plane
  int64_t                      m_NumberOfCells[3];
};
} // namespace itk

#endif
