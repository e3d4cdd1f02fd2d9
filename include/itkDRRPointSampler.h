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
#include "itkDRRPointProjection.h"
#include "PointBasedDRRExport.h"

namespace itk
{
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
 * depend on the seed alone, never on threads. GenerateBatch() is const and called concurrently.
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

  /** Run-time type information (and related methods). */
  itkTypeMacro(DRRPointSampler, Object);

  /** Builds the sampling tables for a volume. The volume must outlive the sampler's use. */
  virtual void
  Initialize(const DRRAttenuationVolume & volume) = 0;

  /** Total attenuation mass M = sum mu * voxel volume (mm^2) of the volume the sampler was built for. */
  itkGetConstMacro(TotalMass, double);

  /** Largest weight GenerateBatch() can return (1 for exact importance samplers). */
  itkGetConstMacro(MaximumWeight, double);

  /** Where a batch sits among the samples of a render. The samples [0, N) are cut into strata, independent
   * replicates of the render (one stratum unless the sampler's points are dependent, see
   * HasIndependentSamples()). Strata are runs of consecutive samples, and a batch lies inside one; or, for samplers
   * that InterleavesStrata(), NumberOfStrata strata share one run and the sampler says which stratum each sample
   * belongs to. */
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

  /** Fills voxelIndex[0 .. range.Count) (linear index, x fastest) and weight[0 .. range.Count). */
  virtual void
  GenerateBatch(DRRPhiloxRandom & random, const SampleRange & range, uint64_t * voxelIndex, double * weight) const = 0;

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
  };

  /** What GenerateCoordinates() fills, one entry per sample of the range: voxel coordinates (i, j, k), weights, the
   * stratum of each sample (interleaving samplers only) and the jitter (ProvidesJitter() samplers only). I, J and K
   * have room for CoordinateSlack entries past the range, which a sampler may overwrite (branch-free stores). */
  static constexpr uint64_t CoordinateSlack = 8;
  /** The arrays GenerateCoordinates() fills (see above). */
  struct CoordinateBatch
  {
    uint32_t * I;       ///< voxel index along x
    uint32_t * J;       ///< voxel index along y
    uint32_t * K;       ///< voxel index along z
    double *   Weight;  ///< sampler weight q / P of each sample
    uint32_t * Stratum; ///< stratum of each sample (samplers that InterleavesStrata() only)
    uint32_t * JitterX; ///< 32 uniform bits for the kernel's offset along x (samplers that ProvidesJitter() only)
    uint32_t * JitterY; ///< the same along y
    uint32_t * JitterZ; ///< the same along z
  };

  /** True if the sampler implements GenerateCoordinates(), which then replaces GenerateBatch() in renders: voxel
   * coordinates instead of linear indices (no divisions), and a cursor (no search per batch). */
  virtual bool
  GeneratesCoordinates() const
  {
    return false;
  }
  /** Fills batch[0 .. range.Count) (see CoordinateBatch) for the samples of range, continuing from cursor and leaving
   * it where the batch ended. Called concurrently (one cursor per thread). Only for samplers that
   * GeneratesCoordinates(); the default does nothing. */
  virtual void
  GenerateCoordinates(const SampleRange &, Cursor &, const CoordinateBatch &) const
  {}

  /** True (default) if the points are independent draws: the renderer then estimates the standard error from the
   * points themselves. False (stratified, Markov chains): from the spread of independent strata. */
  virtual bool
  HasIndependentSamples() const
  {
    return true;
  }

  /** True if the sampler also chooses where inside the voxel each point goes (GenerateCoordinates() then fills the
   * jitter: one uniform 32-bit word per sample and axis, each uniform on its own so that the kernel's offsets keep
   * their law, the point its density); false (default): the renderer draws the kernel's offsets from an independent
   * stream. Only for samplers that GeneratesCoordinates(). */
  virtual bool
  ProvidesJitter() const
  {
    return false;
  }

  /** True if the sampler draws its strata as one run, telling the stratum of every sample (GenerateCoordinates()),
   * so that one walk through its tables serves all strata. The renderer then draws ceil(N / R) samples per stratum.
   * Only for dependent samplers that GeneratesCoordinates(). */
  virtual bool
  InterleavesStrata() const
  {
    return false;
  }

  /** For dependent samplers, the number of strata that serves them best (the renderer's default). 16 gives a steady
   * standard-error image (15 degrees of freedom); a stratified sampler loses accuracy with every extra stratum. */
  virtual unsigned int
  GetPreferredNumberOfStrata() const
  {
    return 16;
  }

  /** Frustum culling: restricts sampling to the voxels whose points can land on the detector of the view (a point
   * can move kernelReach voxels from its voxel centre and share itself with pixels up to pixelReach pixels from its
   * own), or lifts the restriction (null projection). Unbiased: the voxels left out contribute nothing to any pixel.
   * Default: no culling. A sampler culls for one view at a time. */
  virtual void
  SetView(const DRRPointProjection * /* projection */, double /* kernelReach */, double /* pixelReach */)
  {}

  /** The attenuation mass (mm^2, volume frame) the sampler draws from: GetTotalMass(), or the part inside the view
   * after SetView(). */
  virtual double
  GetSampledMass() const
  {
    return m_TotalMass;
  }

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

  /** Total attenuation mass M of the volume, mm^2: set by Initialize(). */
  double m_TotalMass{ 0.0 };
  /** Largest weight GenerateBatch() can return: set by Initialize(). */
  double m_MaximumWeight{ 1.0 };
};
} // namespace itk

#endif
