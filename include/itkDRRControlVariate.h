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
#ifndef itkDRRControlVariate_h
#define itkDRRControlVariate_h

#include "itkDRRCompatibility.h"
#include "itkDRRAttenuationVolume.h"
#include "itkDRRPointProjection.h"
#include "itkDRRPointRenderer.h"
#include "PointBasedDRRExport.h"

#include <functional>
#include <memory>
#include <vector>

namespace itk
{
/** \class DRRControlVariate
 * \brief The split mu = mu_c + r of a box-model volume into an exact coarse part and a signed residual (DESIGN 10).
 *
 * mu_c is the volume coarsened by a factor F per axis: block means of F^3 voxels, the volume padded with air to a
 * multiple of F, so a coarse voxel is the box of its F^3 fine voxels. r = mu - mu_c is piecewise constant on the fine
 * voxels of the padded grid (the padding holds r = -mu_c). For every pixel L[mu] = L[mu_c] + L[r]:
 * - the coarse image L[mu_c] is integrated exactly (Siddon) along antithetic ray pairs in the strata of the splat's
 * footprint (AddCoarseImage()), so that it estimates the same pixel average as the points, without bias;
 * - the residual is sampled by points with density |r| / M_r (M_r = sum |r_v| V, GetResidualMass()), each carrying
 *   the sign of its voxel's r: any sampler initialized on GetResidualVolume() (|r| per voxel) draws them, and the
 *   renderer flips the weight of a point drawn where r < 0 (DRRAttenuationVolume::IsNegativeResidual(),
 *   DRRPointRenderer::Settings::SignedResidual).
 *
 * At equal N the residual's error scales by M_r / M against plain sampling, where the coarse image explains most of
 * the mass; the coarse image costs 4 raysPerSide^2 rays per pixel (two replicates of raysPerSide^2 antithetic pairs)
 * through F^3 fewer voxels.
 *
 * Tables: the coarse volume alone (4 / F^3 bytes per voxel); |r| and its sign are computed from the volume's keys
 * and the coarse means where they are read (DRRAttenuationVolume::BuildResidual()).
 *
 * \sa PointBasedDRRImageFilter::SetControlVariateFactor()
 * \ingroup PointBasedDRR
 */
class PointBasedDRR_EXPORT DRRControlVariate : public Object
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(DRRControlVariate);

  /** Standard class type aliases. */
  using Self = DRRControlVariate;
  using Superclass = Object;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;
  /** Nearest or Bilinear splat (the footprint of the coarse image's rays). */
  using SplatEnum = PointBasedDRREnums::Splat;

  /** Method for creation through the object factory. */
  itkNewMacro(Self);

  /** Run-time type information (and related methods). */
  itkOverrideGetNameOfClassMacro(DRRControlVariate);

  /** A control variate of a volume read slab by slab (docs/design.md section 16), for its coarse image alone: the
   * coarse volume of the whole, wholeSize voxels with this index-to-physical matrix and first voxel centre, assembled
   * from the coarse planes of the slabs' own control variates (AddSlab()) and finished by EndSlabs(). The slabs start
   * at multiples of F planes, so that a slab's blocks are the whole volume's and its own residual is the whole one's
   * there. totalMass: the whole volume's M (mm^2). */
  void
  BeginSlabs(const DRRAttenuationVolume::SizeType &   wholeSize,
             const DRRAttenuationVolume::MatrixType & indexToPhysical,
             const DRRAttenuationVolume::PointType &  origin,
             unsigned int                             factor);
  /** Copies the coarse planes of slab, the control variate (of factor F) of the whole volume's planes from
   * firstPlane (a multiple of F) on, and adds its mass to the total. */
  void
  AddSlab(const DRRControlVariate & slab, uint64_t firstPlane);
  /** Builds the coarse volume of the planes the slabs gave. */
  void
  EndSlabs(MultiThreaderBase * threader);

  /** The factor that stands for "choose F for the volume and the view" (ChooseFactor()) in the settings of the filters
   * and of pbdrr. */
  static constexpr unsigned int AutomaticFactor = 0xFFFFFFFFu;

  /** Largest coarsening factor F: a coarse voxel of 4096 fine voxels a side is no longer a model of anything. */
  static constexpr unsigned int MaximumFactor = 4096;

  /** Splits volume (its box model; levels or mu per voxel) with coarsening factor F (2 .. MaximumFactor; larger than
   * the volume is allowed: one coarse voxel), on the threads of threader (null: platform threads of its own). The
   * residual volume reads the volume's rows: it keeps a reference to it. */
  void
  Build(const DRRAttenuationVolume & volume, unsigned int factor, MultiThreaderBase * threader);

  /** Rows of |r| (1/mm) on the residual's grid (GetResidualVolume()), handed out by Build() while they are in the
   * cache: the rows y FirstRow .. FirstRow + NumberOfRows - 1 of the planes z FirstPlane .. FirstPlane +
   * NumberOfPlanes - 1, whole (Width voxels, x from 0), row (y, z) at Mu + Width (y - FirstRow + NumberOfRows
   * (z - FirstPlane)). FirstRow and FirstPlane are multiples of 8, and so are NumberOfRows and NumberOfPlanes except
   * at the grid's end: each set of rows is whole bricks of 8 x 8 rows. */
  struct ResidualRows
  {
    uint64_t      FirstRow;       ///< y of the first row
    uint64_t      FirstPlane;     ///< z of the first row
    uint64_t      NumberOfRows;   ///< rows per plane
    uint64_t      NumberOfPlanes; ///< planes
    uint64_t      Width;          ///< voxels per row: the residual's size along x
    const float * Mu;             ///< |r| of the rows, 1/mm
  };
  /** What Build() calls with each set of the residual's rows, on its threads (several sets at once). */
  using ResidualRowsFunctionType = std::function<void(const ResidualRows & rows)>;

  /** Build(), handing every row of |r| to visit once, in sets of whole bricks of rows (ResidualRows): a sampler's
   * tables of the residual (DRRPointSampler::InitializeWithControlVariate()) made in the same pass as the coarse
   * volume. With F 2, 4, 8 or 16 each of the volume's rows is read once for both, its blocks summed and its residual
   * taken while it is in the cache; with another F the coarse volume comes first and the residual's rows are then
   * computed from the volume's again. The coarse volume and the residual are those of Build() without visit, bit for
   * bit. */
  void
  Build(const DRRAttenuationVolume &     volume,
        unsigned int                     factor,
        MultiThreaderBase *              threader,
        const ResidualRowsFunctionType & visit);

  /** Throws unless factor is a coarsening factor F: 2 .. MaximumFactor. */
  static void
  VerifyFactor(unsigned int factor);

  /** The size of the residual's grid (GetResidualVolume()) for a volume of the given size and factor F: the size
   * padded to a multiple of F per axis. Throws for a factor that is not one (VerifyFactor()). */
  static DRRAttenuationVolume::SizeType
  ComputeResidualSize(const DRRAttenuationVolume::SizeType & size, unsigned int factor);

  /** The coarsening factor F per axis (0 before Build()). */
  itkGetConstMacro(Factor, unsigned int);

  /** mu_c: the block means, ceil(n / F) voxels per axis, each the box of F^3 voxels of the fine grid. */
  const DRRAttenuationVolume &
  GetCoarseVolume() const
  {
    return *m_CoarseVolume;
  }

  /** |r| on the fine grid padded to a multiple of F (same index-to-physical mapping as the fine volume): what a
   * sampler of the residual is initialized with. */
  const DRRAttenuationVolume &
  GetResidualVolume() const
  {
    return *m_ResidualVolume;
  }

  /** M = sum mu_v V of the fine volume, mm^2. */
  itkGetConstMacro(TotalMass, double);
  /** M_r = sum |r_v| V, mm^2: at equal N, the residual's error is M_r / M of plain sampling's. Its pass over the
   * residual is made on the first call (a sampler initialized on the residual has it too: GetTotalMass()). */
  double
  GetResidualMass() const;

  /** Renders the coarse image for projection (built for the fine volume) with two replicates of raysPerSide^2 rays per
   * pixel drawn from the splat's footprint (streams of seed) and adds it to a render of the residual's points: the line
   * integral becomes L_c + L_r and the standard error sqrt(se_c^2 + se_r^2). threader: not null. replicates 1: one
   * replicate, half the rays, for a render that needs no standard error (se_c is then 0). */
  void
  AddCoarseImage(const DRRPointProjection & projection,
                 SplatEnum                  splat,
                 unsigned int               raysPerSide,
                 uint64_t                   seed,
                 MultiThreaderBase *        threader,
                 ProcessObject *            progressFilter,
                 DRRPointRenderer::Result & result,
                 unsigned int               replicates = 2) const;

  /** The factor `auto` picks for a volume and a view. One pose: the largest power of two (2 to 8) at which a coarse
   * voxel is at most half as wide as the footprint of a detector pixel at the volume's centre, and 2 when none is (the
   * fastest at equal error on the chest, the head and the 2x chest: docs/benchmark/auto_choice.md). Points kept for
   * `poses` > 1 poses (a batch) pay the coarse image at every pose and the points once: the factor from that one up to
   * 16 that the cost model (AutomaticCostModel) predicts fastest at the error of `samples` points at that one (see
   * docs/design.md, section 10). */
  static unsigned int
  ChooseFactor(const DRRAttenuationVolume & volume,
               const DRRPointProjection &   projection,
               uint64_t                     samples = DRRPointRenderer::DefaultNumberOfSamples,
               uint64_t                     poses = 1);
  /** The same, for a volume of size voxels of voxelVolume mm^3 known by its grid alone (a streamed render's). */
  static unsigned int
  ChooseFactor(const DRRAttenuationVolume::SizeType & size,
               double                                 voxelVolume,
               const DRRPointProjection &             projection,
               uint64_t                               samples = DRRPointRenderer::DefaultNumberOfSamples,
               uint64_t                               poses = 1);

  /** What `auto` predicts a render with points kept for several poses to cost, measured on a 2-core Xeon
   * (benchmark/auto_choice.sh; only the ratio of the coarse image's cost to the points' decides). */
  struct AutomaticCostModel
  {
    /** CPU ns per detector pixel and pose of the coarse image: a fixed part, and a part per coarse voxel crossed. */
    static constexpr double PixelNanoseconds = 360.0;
    /** CPU ns per detector pixel, pose and coarse voxel along the ray (the rays of one pixel at the default count). */
    static constexpr double PixelNanosecondsPerCoarseVoxel = 4.4;
    /** CPU ns to draw and splat one point of the residual. */
    static constexpr double PointNanoseconds = 25.0;
    /** CPU ns to splat a kept point at one more pose. */
    static constexpr double KeptPointNanoseconds = 3.0;
    /** M_r(F) grows as F to this power (measured on the chest: 0.078, 0.129, 0.198 of M at F = 2, 4, 8). */
    static constexpr double ResidualMassExponent = 0.7;
    /** The points needed at equal error grow as M_r to this power (2 for independent points; stratified sampling
     * measured 1.6: 2 is the cautious choice). */
    static constexpr double PointsExponent = 2.0;
  };

  /** Bytes held by the split's tables (the coarse volume, and |r| if a consumer materialized it). */
  size_t
  GetTableSizeInBytes() const;

protected:
  DRRControlVariate();
  ~DRRControlVariate() override = default;
  void
  PrintSelf(std::ostream & os, Indent indent) const override;

private:
  void
  BuildCoarseVolume(const DRRAttenuationVolume & volume, MultiThreaderBase * threader);
  /** The coarse volume, and the residual's rows handed to visit, from one read of the volume's rows in sets of
   * max(8, F) x max(8, F) rows: for F 2, 4, 8 and 16, whose blocks fit in such sets. */
  void
  BuildInSetsOfRows(const DRRAttenuationVolume &     volume,
                    MultiThreaderBase *              threader,
                    const ResidualRowsFunctionType & visit);
  /** Hands the residual's rows, computed from the residual volume, to visit in sets of 8 x 8 rows. */
  void
  VisitResidualRows(MultiThreaderBase * threader, const ResidualRowsFunctionType & visit) const;
  /** The coarse volume's index-to-physical matrix and origin for the fine grid of volume. */
  void
  SetCoarseGrid(const DRRAttenuationVolume & volume);

  unsigned int                   m_Factor{ 0 };
  std::unique_ptr<float[]>       m_SlabCoarseMu; // the coarse planes the slabs gave so far (BeginSlabs() .. EndSlabs())
  DRRAttenuationVolume::SizeType m_SlabCoarseSize{ { 0, 0, 0 } };
  double                         m_TotalMass{ 0.0 };
  DRRAttenuationVolume::Pointer  m_CoarseVolume;
  DRRAttenuationVolume::Pointer  m_ResidualVolume;
};
} // namespace itk

#endif
