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
#ifndef itkDRRRenderPlan_h
#define itkDRRRenderPlan_h

// Private to the renderer (src/): what a render decides before it draws a point. The strata of its samples, the
// fixed-point scales of its sums, and the checks and reaches of its settings.

#include "itkDRRPointRenderer.h"

#include <array>
#include <cstdint>
#include <vector>

namespace itk
{
namespace DRRRendering
{
/** The strata of a render. Contiguous: R runs of consecutive samples, of N / R samples each (up to one).
 * Interleaved (DRRSamplerTraits::InterleavesStrata): R strata of ceil(N / R) samples each, drawn as one run in which
 * the sampler tells the stratum of every sample. */
class Strata
{
public:
  Strata(uint64_t numberOfSamples, uint64_t numberOfStrata, bool interleaved);
  /** Samples drawn (N, or R ceil(N / R) when interleaved). */
  uint64_t
  GetNumberOfSamples() const
  {
    return m_First.back();
  }
  uint64_t
  GetNumberOfStrata() const
  {
    return m_NumberOfStrata;
  }
  bool
  IsInterleaved() const
  {
    return m_Interleaved;
  }
  uint64_t
  Size(uint64_t stratum) const
  {
    return m_Interleaved ? m_InterleavedSize : this->RunSize(stratum);
  }
  /** Runs of consecutive samples (the strata, or the one run of interleaved strata). */
  uint64_t
  RunOfSample(uint64_t sample) const;
  uint64_t
  RunFirst(uint64_t run) const
  {
    return m_First[run];
  }
  uint64_t
  RunSize(uint64_t run) const
  {
    return m_First[run + 1] - m_First[run];
  }
  /** Chunks of DRRPointRenderer::SamplesPerChunk samples (the last one may be shorter). */
  uint64_t
  GetNumberOfChunks() const
  {
    return (this->GetNumberOfSamples() + DRRPointRenderer::SamplesPerChunk - 1) / DRRPointRenderer::SamplesPerChunk;
  }

private:
  uint64_t              m_NumberOfStrata;
  bool                  m_Interleaved;
  uint64_t              m_InterleavedSize{ 0 };
  std::vector<uint64_t> m_First;
};

/** The part of a render that one slab of a streamed render draws (docs/design.md section 16): the samples [First, End)
 * of the run, whose voxels' z planes (the slab's own) are shifted by FirstPlane, the slab's first plane in the whole
 * volume. The default is the whole render. */
struct SlabWindow
{
  uint64_t First{ 0 };
  uint64_t End{ UINT64_MAX };
  uint32_t FirstPlane{ 0 };
};

/** The strata a sampler's points form in a render of settings.NumberOfSamples points. */
Strata
MakeStrata(const DRRSamplerTraits & traits, const DRRPointRenderer::Settings & settings);

/** Fixed-point scales of a render: every contribution is rounded once to an integer of these scales (see
 * PlanFixedPoint()). */
struct FixedPoint
{
  int  SumExponent{ 0 };
  int  SquareExponent{ 0 };
  bool Small{ false }; // every fixed-point value below 2^51: the rounding that vectorizes (see PointSplatter)
};

/** Bounds the contributions so that the fixed-point sums cannot overflow; may set the projection's minimum depth and
 * says so in the result (see the definition). */
FixedPoint
PlanFixedPoint(double                        numberOfSamples,
               double                        maximumWeight,
               const std::array<double, 3> & lower,
               const std::array<double, 3> & upper,
               bool                          unbiased,
               DRRPointProjection &          projection,
               DRRPointRenderer::Result &    result);

/** Throws unless settings.NumberOfSamples >= DRRPointRenderer::MinimumNumberOfSamples. */
void
VerifyNumberOfSamples(const DRRPointRenderer::Settings & settings);

/** Throws unless settings.NumberOfChannels is 1 to 256 and, above 1, the voxels' channels are given. */
void
VerifyChannels(const DRRPointRenderer::Settings & settings);

/** A result of zeros for the projection's detector, with zero channel images for more than one channel. */
DRRPointRenderer::Result
ZeroResult(const DRRPointProjection & projection, unsigned int numberOfChannels = 1);

/** The continuous-index box [lower, upper] the kernel's points reach in a volume of size voxels per axis. */
void
KernelSupport(PointBasedDRREnums::ReconstructionKernel kernel,
              const std::array<uint64_t, 3> &          size,
              std::array<double, 3> &                  lower,
              std::array<double, 3> &                  upper);

/** How far from its voxel centre the kernel moves a point, voxels. */
double
KernelReach(PointBasedDRREnums::ReconstructionKernel kernel);

/** How far from a point the pixel centres its splat reaches are, pixels. */
double
SplatReach(PointBasedDRREnums::Splat splat);
} // namespace DRRRendering
} // namespace itk

#endif
