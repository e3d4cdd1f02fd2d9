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
 * RenderFootprintAverages() instead draws antithetic ray pairs in the strata of the splat's footprint: an unbiased
 * estimate of the pixel average a point render estimates, with its standard error (DESIGN 10, the control variate).
 *
 * A coarse volume whose voxel c is the box of the F^3 voxels F c .. F c + F - 1 of a finer grid (DRRControlVariate)
 * is integrated in the finer grid's index space: the projection is the finer volume's, indexCoarsening is F.
 *
 * \sa ExactDRRImageFilter
 * \ingroup PointBasedDRR
 */
class PointBasedDRR_EXPORT DRRExactRayIntegrator
{
public:
  /** Box (Siddon) or Tent (trilinear) voxel model. */
  using KernelEnum = PointBasedDRREnums::ReconstructionKernel;
  /** Nearest or Bilinear splat (the footprint of RenderFootprintAverages()). */
  using SplatEnum = PointBasedDRREnums::Splat;

  /** Integrates through the box or tent model of a volume, which must outlive the integrator (it is not copied); throws
   * ExceptionObject for a kernel whose model has no exact projector here (DRRBoxKernel::ExactReference). The ray
   * methods take continuous indices of a grid indexCoarsening times finer than the volume's (1: the volume's own; more
   * for the box model only), whose projections they are given. */
  DRRExactRayIntegrator(const DRRAttenuationVolume & volume, KernelEnum kernel, unsigned int indexCoarsening = 1);

  /** Integral of mu over the parameter t in [0, 1] of the segment p0 -> p1 (continuous index coordinates of the
   * volume's own grid): multiply by the segment's length in mm to get the line integral. With channels (not null; a
   * volume with channels, DRRAttenuationVolume::GetVoxelChannels()), also adds channelScale times the integral of
   * each channel's part of mu to channels[k] (the box model: the voxel's channel; the tent model: each corner's). */
  double
  IntegrateSegment(const double p0[3],
                   const double p1[3],
                   double *     channels = nullptr,
                   double       channelScale = 1.0) const;

  /** Line integral (dimensionless) along one ray through the detector point (column, row), fractional allowed. With
   * channels (not null, a volume with channels), also adds each channel's line integral to channels[k]. */
  double
  IntegrateRay(const DRRPointProjection & projection, double column, double row, double * channels = nullptr) const;

  /** About the number of cells of the model's grid the ray IntegrateRay() traces crosses (1 plus the planes it
   * crosses; 0 for a ray that misses the grid): the ray's work, for a cost model (DRREstimatorChoice). */
  double
  CountCrossedCells(const DRRPointProjection & projection, double column, double row) const;

  /** The cache lines (CacheLineBytes of the volume's voxels, x fastest) of the cells the ray through (column, row)
   * crosses, in the order it reads them, a line read again at once listed once: which of a ray's reads a neighbouring
   * ray has made warm, for a cost model (DRREstimatorChoice). */
  std::vector<uint64_t>
  ListReadCacheLines(const DRRPointProjection & projection, double column, double row) const;

  /** Bytes of a cache line, for ListReadCacheLines(). */
  static constexpr uint64_t CacheLineBytes = 64;

  /** The projection image (cols x rows, columns fastest; dimensionless line integrals): the average of raysPerSide^2
   * rays per pixel, on the threads of threader (not null), reporting progress to progressFilter (may be null), which
   * is also checked for abort. With channelImage (not null) and a volume with K channels, also each channel's
   * image into it, K values per pixel (pixel major); the image is the same bits either way, and the channels add up
   * to it within rounding. */
  std::vector<double>
  RenderProjection(const DRRPointProjection & projection,
                   unsigned int               raysPerSide,
                   MultiThreaderBase *        threader,
                   ProcessObject *            progressFilter,
                   std::vector<double> *      channelImage = nullptr) const;

  /** Unbiased estimates of every pixel's footprint average of the line integral, (1 / a) * integral of share(x) L(x)
   * dx over the detector, with share the splat's (DRRNearestSplat::FootprintOffset()): two independent replicates of
   * raysPerSide^2 antithetic ray pairs per pixel, one pair per cell of a regular raysPerSide x raysPerSide
   * stratification of the footprint's distribution (a ray jittered in its cell and its mirror through the cell's
   * centre), drawn from the streams of seed (the same bits on any number of threads).
   * standardError: half the replicates' difference, an unbiased estimate of the variance of their mean (one degree
   * of freedom per pixel; a stratified sample's variance has no unbiased estimate from one replicate, and the spread
   * of its rays overstates it, 2 to 4 times on the test phantoms). cols x rows, columns fastest, on the threads of
   * threader (not null), reporting progress to progressFilter (may be null). replicates 1: the first replicate alone,
   * half the rays, for a render that needs no standard error (standardError is then zero). */
  void
  RenderFootprintAverages(const DRRPointProjection & projection,
                          SplatEnum                  splat,
                          unsigned int               raysPerSide,
                          uint64_t                   seed,
                          MultiThreaderBase *        threader,
                          ProcessObject *            progressFilter,
                          std::vector<double> &      image,
                          std::vector<double> &      standardError,
                          unsigned int               replicates = 2) const;

private:
  using MuReaderType = DRRAttenuationVolume::MuReader;

  /** Siddon's traversal of the box model from the entry cell to tExit (the cursors of IntegrateSegment()): the
   * integral of mu over the segment's parameter. VDominant: the axis of most planes, whose steps take the short path.
   */
  template <bool VChannels, unsigned int VDominant>
  double
  TraverseBox(MuReaderType  mu,
              const int64_t cell[3],
              const int64_t step[3],
              const double  tNext[3],
              const double  tDelta[3],
              double        tEnter,
              double        tExit,
              double *      channels,
              double        channelScale) const;

  /** The traversal's start at tEnter on the segment p0 + t d: the cell, the step along each axis (-1, 0, 1), the
   * parameter of the next plane of each axis and between two of them (infinity for an axis not crossed). */
  void
  StartTraversal(const double p0[3],
                 const double d[3],
                 double       tEnter,
                 int64_t      cell[3],
                 int64_t      step[3],
                 double       tNext[3],
                 double       tDelta[3]) const;

  /** Clips the segment p0 -> p1 (continuous indices) to the grid's cells: its direction into d and the parameters
   * of entry and exit (within the tEnter .. tExit given); false if it misses them. */
  bool
  ClipToGrid(const double p0[3], const double p1[3], double d[3], double & tEnter, double & tExit) const;

  /** The ray's segment through the model's support (continuous indices of the volume's own grid); returns its
   * length, mm. */
  double
  ComputeRaySegment(const DRRPointProjection & projection, double column, double row, double p0[3], double p1[3]) const;

  /** mu of the 8 corners of the cell whose lower corner is voxel corner (zero in the padding) and their linear
   * indices; corner c is (c & 1, (c >> 1) & 1, c >> 2) from it. */
  void
  ReadCorners(const MuReaderType & mu, const int64_t corner[3], double cornerMu[8], uint64_t cornerVoxel[8]) const;

  /** The trilinear interpolant in a cell (its corners' mu and indices, ReadCorners(); the fractions); with channels,
   * also adds channelScale times each corner's term to its voxel's channel. */
  double
  Trilinear(const double   cornerMu[8],
            const uint64_t cornerVoxel[8],
            const double   fraction[3],
            double *       channels,
            double         channelScale) const;

  const DRRAttenuationVolume & m_Volume;
  bool                         m_Siddon;          // the box model's Siddon traversal, or else the trilinear one
  double                       m_GridStart;       // continuous index of the first grid plane
  double                       m_IndexCoarsening; // F: the projection's index = F (own index + 0.5) - 0.5
  int64_t                      m_NumberOfCells[3];
};
} // namespace itk

#endif
