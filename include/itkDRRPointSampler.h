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

#include "itkDRRCompatibility.h"
#include "itkDRRAttenuationVolume.h"
#include "itkDRRPhiloxRandom.h"
#include "itkDRRPointProjection.h"
#include "itkDRRSamplerTraits.h"
#include "itkDRRSamplerViewPlan.h"
#include "PointBasedDRRExport.h"

#include <memory>
#include <string>

namespace itk
{
class DRRControlVariate;

/** \class DRRPointSampler
 * \brief Policy that draws the voxels of a point-based DRR, a batch at a time.
 *
 * A sampler draws voxel v with some probability P(v) and returns, with each voxel, the weight q(v) / P(v), where
 * q(v) = mu_v * voxelVolume / M is the exact importance density: every sampler therefore estimates the same line
 * integrals (docs/design.md section 2). Where inside the voxel the point goes is the reconstruction kernel's business,
 * not the sampler's.
 *
 * Batches are addressed by sample index (SampleRange): a sampler may use the index (stratified samplers do) and must
 * draw its random numbers from the stream it is handed or from streams keyed by the seed and stratum, so that results
 * depend on the seed alone, never on threads. GenerateBatch() and GenerateCoordinates() are const and called
 * concurrently.
 *
 * The renderer asks three things: GetTraits() (how the points behave), MakeViewPlan() (what to draw from for a view:
 * an immutable plan, held for the render; a render never changes the sampler) and GenerateCoordinates() (the points
 * of a batch). A simple sampler writes only Initialize() and GenerateBatch() (linear voxel indices): the default
 * GenerateCoordinates() turns them into coordinates, and the default plan is the whole volume.
 *
 * A new sampler is one subclass and one line in itkDRRSamplerFactory.cxx.
 *
 * \sa DRRSamplerFactory, PointBasedDRRImageFilter::SetSampler(), DRRLevelAliasSampler, DRRStratifiedSampler,
 * DRRMetropolisSampler, DRRPaperHybridSampler, DRRUniformVolumeSampler
 * \ingroup PointBasedDRR
 */
class PointBasedDRR_EXPORT DRRPointSampler : public Object
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(DRRPointSampler);

  /** Standard class type aliases. */
  using Self = DRRPointSampler;
  using Superclass = Object;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  /** The random stream a sampler draws from: counter-based, keyed by the render's seed and addressed by chunk, so that
   * a seeded render is the same on any number of threads. An engine type (itk::detail), named here for samplers. */
  using RandomType = detail::DRRPhiloxRandom;

  /** Run-time type information (and related methods). */
  itkOverrideGetNameOfClassMacro(DRRPointSampler);

  /** Builds the sampling tables for a volume. The volume must outlive the sampler's use. */
  virtual void
  Initialize(const DRRAttenuationVolume & volume) = 0;

#if !defined(ITK_WRAPPING_PARSER)
  /** Splits volume with a control variate of factor F (controlVariate.Build()) and builds the sampling tables of its
   * residual, as Initialize(controlVariate.GetResidualVolume()) builds them. The default does one after the other; a
   * sampler whose tables are made from the rows of the volume it samples overrides it to make them in the split's own
   * pass (DRRControlVariate::ResidualRows), one read of the volume instead of two. Not wrapped: the control variate is
   * the engine's. */
  virtual void
  InitializeWithControlVariate(DRRControlVariate &          controlVariate,
                               const DRRAttenuationVolume & volume,
                               unsigned int                 factor,
                               MultiThreaderBase *          threader);
#endif

  /** Total attenuation mass M = sum mu * voxel volume (mm^2) of the volume the sampler was built for. */
  itkGetConstMacro(TotalMass, double);

  /** Largest weight GenerateBatch() can return (1 for exact importance samplers). */
  itkGetConstMacro(MaximumWeight, double);

  /** How the sampler's points behave (see DRRSamplerTraits); the default: independent points, nothing more. */
  virtual DRRSamplerTraits
  GetTraits() const
  {
    return DRRSamplerTraits{};
  }

  /** Where a batch sits among the samples of a render. The samples [0, N) are cut into strata, independent
   * replicates of the render (one stratum unless the sampler's points are dependent, see
   * DRRSamplerTraits::IndependentSamples). Strata are runs of consecutive samples, and a batch lies inside one; or, for
   * samplers that interleave strata (DRRSamplerTraits::InterleavesStrata), NumberOfStrata strata share one run and the
   * sampler says which stratum each sample belongs to. */
  struct SampleRange
  {
    uint64_t Seed{ 0 };           ///< seed of the render
    uint64_t First{ 0 };          ///< first sample of the batch
    uint64_t Count{ 0 };          ///< samples in the batch
    uint64_t Stratum{ 0 };        ///< index of the run (of the stratum, unless interleaved)
    uint64_t StratumFirst{ 0 };   ///< first sample of the run
    uint64_t StratumSize{ 0 };    ///< samples in the run
    uint64_t NumberOfStrata{ 1 }; ///< strata interleaved in the run (each of StratumSize / NumberOfStrata samples)
  };

  /** Fills voxelIndex[0 .. range.Count) (linear index, x fastest) and weight[0 .. range.Count), drawing from random:
   * the one method a simple sampler writes (the default GenerateCoordinates() calls it). A sampler that overrides
   * GenerateCoordinates() instead need not write it: the default throws. */
  virtual void
  GenerateBatch(RandomType & random, const SampleRange & range, uint64_t * voxelIndex, double * weight) const;

  /** Where a sampler left off in a chunk: the renderer hands the same cursor to the consecutive batches of one chunk
   * (invalid at the start of every chunk), so a sampler that walks its tables in order need not search them again.
   * Only the sampler reads its contents; what it draws must not depend on them (only on the range), which keeps a
   * render independent of the threads. */
  struct Cursor
  {
    bool     Valid{ false }; ///< false at the start of a chunk: the sampler must position the cursor first
    uint64_t Stratum{ 0 };   ///< the stratum the cursor is in (the sampler's to use)
    uint64_t Position[4]{};  ///< where in its tables, in the sampler's own terms
    double   Mass[2]{};      ///< masses the sampler keeps with the position (1/mm, in its own terms)
    uint64_t CachedGroup{ ~uint64_t{ 0 } }; ///< which values Cached holds, in the sampler's own terms (none: all ones)
    float    Cached[64];                    ///< values the sampler read from the volume near the position (its own)
  };

  /** What GenerateCoordinates() fills, one entry per sample of the range: voxel coordinates (i, j, k), weights, the
   * stratum of each sample (samplers that interleave strata only) and the jitter (samplers that provide it only). I,
   * J and K have room for CoordinateSlack entries past the range, which a sampler may overwrite (branch-free stores).
   */
  static constexpr uint64_t CoordinateSlack = 8;
  /** The arrays GenerateCoordinates() fills (see above). */
  struct CoordinateBatch
  {
    uint32_t * I;       ///< voxel index along x
    uint32_t * J;       ///< voxel index along y
    uint32_t * K;       ///< voxel index along z
    double *   Weight;  ///< sampler weight q / P of each sample
    uint32_t * Stratum; ///< stratum of each sample (DRRSamplerTraits::InterleavesStrata samplers only)
    uint32_t * JitterX; ///< 32 uniform bits for the kernel's offset along x (DRRSamplerTraits::ProvidesJitter only)
    uint32_t * JitterY; ///< the same along y
    uint32_t * JitterZ; ///< the same along z
    uint64_t * Voxel;   ///< room for the linear voxel indices of GenerateBatch() (the default GenerateCoordinates())
  };

  /** The plan of a render (see DRRSamplerViewPlan), shared and immutable. */
  using ViewPlanConstPointer = std::shared_ptr<const DRRSamplerViewPlan>;

  /** What to draw from in a render of a view: for a culling sampler (DRRSamplerTraits::CullsToView), only the voxels
   * whose points can land on the detector of the projection (a point can move kernelReach voxels from its voxel centre
   * and share itself with pixels up to pixelReach pixels from its own); the whole volume for a null projection, and
   * for every view by default. Unbiased: the voxels left out contribute nothing to any pixel. volume: the one the
   * sampler was initialized with. Const: the sampler is not changed, the plan holds what the view needs. */
  virtual ViewPlanConstPointer
  MakeViewPlan(const DRRAttenuationVolume & volume,
               const DRRPointProjection *   projection,
               double                       kernelReach,
               double                       pixelReach) const;

  /** Fills batch[0 .. range.Count) (see CoordinateBatch) for the samples of range drawn from plan (made by this
   * sampler's MakeViewPlan()), continuing from cursor and leaving it where the batch ended; random is the chunk's
   * sampler stream. Called concurrently (one cursor per thread). The default calls GenerateBatch() and converts its
   * linear indices to (i, j, k); a sampler that walks its own tables overrides it (voxel coordinates directly, no
   * divisions, and a cursor instead of a search per batch). */
  virtual void
  GenerateCoordinates(const DRRSamplerViewPlan & plan,
                      RandomType &               random,
                      const SampleRange &        range,
                      Cursor &                   cursor,
                      const CoordinateBatch &    batch) const;

  /** Bytes held by the sampling tables. */
  virtual size_t
  GetTableSizeInBytes() const = 0;

  /** One line on what the sampler measured of its own draws (e.g. a Markov chain's acceptance rate), for a user's
   * log (a program's verbose output); empty, the default, if there is nothing to say. */
  virtual std::string
  GetStatisticsSummary() const
  {
    return {};
  }

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

  /** Total attenuation mass M of the volume, mm^2: set by Initialize(). */
  double m_TotalMass{ 0.0 };
  /** Largest weight GenerateBatch() can return: set by Initialize(). */
  double m_MaximumWeight{ 1.0 };
};
} // namespace itk

#endif
