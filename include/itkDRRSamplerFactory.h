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
 * \brief The samplers a user can pick by name (the CLI's --sampler), each registered by one line in
 * itkDRRSamplerFactory.cxx.
 *
 * Names: `level-alias` (DRRLevelAliasSampler, the default), `stratified` (DRRStratifiedSampler), `metropolis`
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
    std::string Name;                     ///< what Create() and the CLI's --sampler take, e.g. `level-alias`
    std::string Description;              ///< one line for the CLI's help
    DRRPointSampler::Pointer (*Create)(); ///< makes a new sampler with its default settings
  };

  /** Every registered sampler, in registration order. */
  static const std::vector<Entry> &
  GetEntries();

  /** A new sampler of that name; throws ExceptionObject listing the names for an unknown one. */
  static DRRPointSampler::Pointer
  Create(const std::string & name);

  /** The registered names, comma separated. */
  static std::string
  GetNames();
};
} // namespace itk

#endif
