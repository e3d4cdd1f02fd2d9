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
#ifndef itkDRRSamplerFactory_h
#define itkDRRSamplerFactory_h

#include "itkDRRPointSampler.h"
#include "PointBasedDRRExport.h"

#include <string>
#include <vector>

namespace itk
{
/** \class DRRSamplerFactory
 * \brief The registry of samplers: the ones a user can pick by name, each registered by one entry in
 * itkDRRSamplerFactory.cxx.
 *
 * The registry is the one list of samplers: programs that offer a choice of sampler (pbdrr's --sampler), the tests
 * that run every sampler (unbiasedness, reuse, robustness, fuzzing) and the checks of the wrapping, the README and
 * docs/wrapping.md are derived from it or checked against it (test PointBasedDRR.PolicyRegistry). A new sampler is its
 * own class and one entry here.
 *
 * Names: `stratified` (DRRStratifiedSampler, the default), `level-alias` (DRRLevelAliasSampler), `metropolis`
 * (DRRMetropolisSampler), `paper-hybrid` (DRRPaperHybridSampler), `mcvr` (DRRUniformVolumeSampler).
 *
 * \code
 *   drr->SetSampler(itk::DRRSamplerFactory::Create("stratified"));
 * \endcode
 *
 * \sa DRRPointSampler, PointBasedDRRImageFilter::SetSampler()
 * \ingroup PointBasedDRR
 */
class PointBasedDRR_EXPORT DRRSamplerFactory
{
public:
  /** A registered sampler. */
  struct Entry
  {
    std::string Name;                     ///< what Create() takes, e.g. `level-alias`
    DRRPointSampler::Pointer (*Create)(); ///< makes a new sampler with its default settings
    /** Makes the sampler as the paper runs it, with the paper's own (biased) counting where that differs from the
     * default (Create(name, true)); null where the sampler has no such variant. */
    DRRPointSampler::Pointer (*CreatePaperVariant)() = nullptr;
  };

  /** The name of the default sampler, of PointBasedDRRImageFilter and of pbdrr: stratified, which measures the least
   * error for the time, plain and with the control variate (docs/performance.md). The registration order is fixed by
   * the fuzzers' seeds (new samplers go at the end), so the default is named here rather than by its place. */
  static constexpr const char * DefaultName = "stratified";

  /** Every registered sampler, in registration order. */
  static const std::vector<Entry> &
  GetEntries();

  /** A new sampler of that name (its paper variant if paperVariant and it has one); throws ExceptionObject listing the
   * names for an unknown one. */
  static DRRPointSampler::Pointer
  Create(const std::string & name, bool paperVariant = false);

  /** The registered names, comma separated. */
  static std::string
  GetNames();
};
} // namespace itk

#endif
