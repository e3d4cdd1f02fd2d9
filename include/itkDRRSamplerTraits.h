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
#ifndef itkDRRSamplerTraits_h
#define itkDRRSamplerTraits_h

namespace itk
{
/** \class DRRSamplerTraits
 * \brief What the renderer needs to know of a sampler to plan a render: one value, from
 * DRRPointSampler::GetTraits(), instead of one virtual question each.
 *
 * The defaults describe a simple sampler of independent points that writes only DRRPointSampler::GenerateBatch():
 * one stratum, the renderer's own jitter, no culling.
 *
 * \sa DRRPointSampler, DRRPointRenderer
 * \ingroup PointBasedDRR
 */
struct DRRSamplerTraits
{
  /** True if the points are independent draws: the renderer then estimates the standard error from the points
   * themselves. False (stratified, Markov chains): from the spread of independent strata. */
  bool IndependentSamples{ true };

  /** True if the sampler also chooses where inside the voxel each point goes (DRRPointSampler::GenerateCoordinates()
   * then fills the jitter: one uniform 32-bit word per sample and axis, each uniform on its own so that the kernel's
   * offsets keep their law, the point its density); false: the renderer draws the kernel's offsets from an
   * independent stream. */
  bool ProvidesJitter{ false };

  /** True if the sampler draws its strata as one run, telling the stratum of every sample
   * (DRRPointSampler::GenerateCoordinates()), so that one walk through its tables serves all strata. The renderer
   * then draws ceil(N / R) samples per stratum. Only for dependent samplers. */
  bool InterleavesStrata{ false };

  /** For dependent samplers, the number of strata that serves them best (the renderer's default). 16 gives a steady
   * standard-error image (15 degrees of freedom); a stratified sampler loses accuracy with every extra stratum. */
  unsigned int PreferredNumberOfStrata{ 16 };

  /** True if DRRPointSampler::MakeViewPlan() restricts sampling to the voxels that can reach the view's detector
   * (frustum culling); false: every plan draws from the whole volume. */
  bool CullsToView{ false };
};
} // namespace itk

#endif
