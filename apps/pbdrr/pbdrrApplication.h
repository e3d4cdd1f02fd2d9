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
#ifndef pbdrrApplication_h
#define pbdrrApplication_h

#include "pbdrrImageOutputs.h"
#include "pbdrrOptions.h"
#include "pbdrrView.h"
#include "pbdrrVolumeLoader.h"

#include "itkDRRImageFilterBase.h"
#include "itkDRRProjectionGeometry.h"
#include "itkDRRTransferFunction.h"
#include "itkDRRXRaySpectrum.h"
#include "itkPointBasedDRRImageFilter.h"

#include <iostream>

namespace pbdrr
{
/** What every renderer is: the point-based filter or an exact projector, of a CT of type TVolume (HUVolumeType or
 * VolumeType: the loaded volume's own). */
template <typename TVolume>
using BaseFilterType = itk::DRRImageFilterBase<TVolume, ProjectionType>;
/** The point-based renderer. */
template <typename TVolume>
using PointFilterType = itk::PointBasedDRRImageFilter<TVolume, ProjectionType>;

/** The renderer the options ask for, its input and transfer function set, its view not. */
template <typename TVolume>
struct Renderer
{
  typename BaseFilterType<TVolume>::Pointer  Filter; ///< the filter that renders (point-based or exact)
  typename PointFilterType<TVolume>::Pointer Points; ///< the same filter if it is point-based, else null (--exact)
};

/** `--stream`: the CT's file opened, its header read, no voxel: a filter requests it slab by slab. A file whose pixel
 * type an int16 holds is read as int16 HU, any other as float, as LoadVolume() reads it; a DICOM series is refused. */
LoadedVolume
OpenStreamedVolume(const std::string & input);

/** The CT's header before the load, for the view and the filter that renders it: OpenStreamedVolume() of a file ITK
 * reads, not DICOM. Unset for a DICOM series or file, which is read whole (no budget streams it), and for a file
 * the load refuses: in the load's words (LoadVolumeAfterHeader()), after the settings' checks. */
LoadedVolume
OpenVolumeHeader(const Options & options);

/** The CT: read whole (LoadVolume()) or, streamed, the header's reader (OpenStreamedVolume() if the header is unset,
 * which refuses a series or a missing or damaged file). */
LoadedVolume
LoadVolumeAfterHeader(const Options &      options,
                      const LoadedVolume & header,
                      bool                 streamed,
                      const LoadProgress & progress);

/** Builds the renderer of the options (sampler, kernel, splat, control variate, or --exact, --stream and
 * --memory-budget) for volume (its header alone, or null before the load). Instantiated for HUVolumeType and
 * VolumeType. */
template <typename TVolume>
Renderer<TVolume>
MakeRenderer(const Options & options, const TVolume * volume);

/** Asks the configured filter, before the load, whether its settings hold: the point filter's VerifySettings() and,
 * with --stream, WhyNotStreamable(). Its refusal is a UsageError in the filter's words: the rules are the filter's,
 * the options chose the settings. */
template <typename TVolume>
void
VerifyRenderSettings(const Options & options, const Renderer<TVolume> & renderer);

/** The slabs the filter will read its input in (GetNumberOfSlabs(): --stream, or as many as its memory budget needs),
 * said on stderr when the budget streams unasked. */
template <typename TVolume>
unsigned int
AnnounceSlabs(const Options & options, const Renderer<TVolume> & renderer);

/** HU (or mu) to attenuation, as --input-units, --energy, --mu-water and --air-threshold say. */
itk::DRRTransferFunction::Pointer
MakeTransferFunction(const Options & options);

/** True if the options ask for a polychromatic beam (--spectrum or --kvp). */
bool
IsPolychromatic(const Options & options);

/** True if the render's standard error is read (--stderr; a polychromatic beam's covariance): the point-based
 * filter computes it (ComputeStandardError) only then. */
bool
ReadsStandardError(const Options & options);

/** -v's lines of --accuracy: the candidates of the choice (if the filter chose), what it chose and why, and the error
 * it estimates. */
template <typename TFilter>
void
PrintAccuracy(const TFilter & filter, double askedPercent)
{
  const itk::DRREstimatorChoice * choice = filter.GetEstimatorChoice(); // null unless the filter chose
  if (choice)
  {
    const auto &       chosen = filter.GetChosenEstimator();
    const unsigned int views = choice->GetNumberOfViews();
    std::cerr << "pbdrr: accuracy: pilot of " << itk::DRREstimatorChoice::PilotGridSide << " x "
              << itk::DRREstimatorChoice::PilotGridSide << " pixels"
              << (views > 1 ? " in each of " + std::to_string(views) + " views" : std::string()) << ": "
              << (views > 1 ? "the first's " : "") << "mean line integral " << choice->GetMeanLineIntegral()
              << ", range " << choice->GetRange() << "; an exact ray crosses " << choice->GetMeanCellsPerRay()
              << " cells and misses the cache " << choice->GetMeanUnforeseenMissesPerRay() << " times"
              << (views > 1 ? " (means), the largest error of the views" : "") << "; predicted error and CPU time to "
              << askedPercent << "%:" << std::endl;
    for (const auto & candidate : filter.GetEstimatorCandidates())
    {
      const bool reaches = candidate.Error <= askedPercent / 100.0;
      std::cerr << "pbdrr: accuracy:   " << candidate.Describe() << ": " << 100.0 * candidate.Error << "% in "
                << candidate.Seconds << " s" << (reaches ? "" : " (misses the target)") << std::endl;
    }
    std::cerr << "pbdrr: accuracy: chose " << chosen.Describe()
              << ", the least predicted work of those that reach the target" << std::endl;
  }
  std::cerr << "pbdrr: accuracy: estimated error " << 100.0 * filter.GetEstimatedError() << "% (asked " << askedPercent
            << "%) with " << filter.GetTotalNumberOfSamples() << " points in all" << std::endl;
}

/** The spectrum of --spectrum FILE or --kvp KV (null for neither); throws for a bad spectrum file. */
itk::DRRXRaySpectrum::Pointer
MakeSpectrum(const Options & options);

/** The filter's image, or with a spectrum (MakeSpectrum()) its polychromatic line integral -ln T from the material
 * channels (DRRPolychromaticImageFilter; standardError then becomes its standard error). */
template <typename TVolume>
ProjectionType::ConstPointer
PolychromaticImage(const Options &                options,
                   const itk::DRRXRaySpectrum *   spectrum,
                   BaseFilterType<TVolume> *      filter,
                   ProjectionType::ConstPointer & standardError);

/** The image with quantum noise (--photons, DRRQuantumNoiseImageFilter seeded by seed), or image itself without. */
ProjectionType::ConstPointer
AddQuantumNoise(const Options & options, const ProjectionType * image, uint64_t seed);

/** Loads, renders and writes as the options say. Throws std::runtime_error (or itk::ExceptionObject) on failure. */
void
Run(const Options & options);

std::string
VersionText();
} // namespace pbdrr

#endif
