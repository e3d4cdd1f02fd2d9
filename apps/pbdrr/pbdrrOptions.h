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
#ifndef pbdrrOptions_h
#define pbdrrOptions_h

#include "itkDRRControlVariate.h"
#include "itkDRRSamplerFactory.h"
#include "itkDRRPointRenderer.h"
#include "itkPointBasedDRREnums.h"
#include "pbdrrOptionTable.h"

#include <array>
#include <functional>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace pbdrr
{
/** Everything the command line says. Geometry fields left empty keep the geometry file's value or the default. */
struct Options
{
  std::string input;
  std::string output;
  std::string standardErrorOutput;
  std::string geometryFile;
  std::string seriesUID;

  std::optional<double>                              sad;
  std::optional<double>                              sid;
  std::optional<double>                              gantryDegrees;
  std::optional<std::array<double, 3>>               isocenter;
  std::optional<std::array<double, 3>>               normal;
  std::optional<std::array<double, 3>>               viewUp;
  std::optional<std::array<double, 2>>               detectorSize; // cols, rows
  std::optional<std::array<double, 2>>               detectorSpacing;
  std::optional<std::array<double, 2>>               detectorOffset;
  std::optional<itk::PointBasedDRREnums::Projection> projection; // --projection NAME, --parallel
  std::string projectionMatrixFile; // --projection-matrix FILE: the view from a 3 x 4 matrix (with --size)
  std::string geometryFrom;         // --geometry-from LOCALIZER.dcm: the localizer's own view and pixel grid

  uint64_t samples{ itk::DRRPointRenderer::DefaultNumberOfSamples };
  /** --accuracy PCT: the estimated relative error to reach, percent (PointBasedDRRImageFilter::SetTargetError()). */
  std::optional<double> accuracyPercent;
  bool        accuracyIsDefault{ false }; // accuracyPercent is pbdrr's default (DefaultAccuracyPercent), not given
  std::string sampler{ itk::DRRSamplerFactory::DefaultName };
  itk::PointBasedDRREnums::ReconstructionKernel kernel{ itk::PointBasedDRREnums::ReconstructionKernel::Box };
  itk::PointBasedDRREnums::Splat                splat{ itk::PointBasedDRREnums::Splat::Nearest };
  uint64_t                                      seed{ 0 };
  unsigned                                      threads{ 0 }; // 0: all
  unsigned                                      stream{ 1 };  // slabs the CT is read in (1: whole)
  std::optional<uint64_t>                       memoryBudget; // bytes (0: none); unset: half the machine's memory
  bool                                          paperCount{ false };
  unsigned                                      strata{ 0 }; // 0: the sampler's preference
  /** --control-variate: the coarsening factor F (0: off; the filter's AutomaticControlVariateFactor: auto, the
   * default, which the filter resolves to off where the control variate does not apply: --paper-count, a kernel
   * other than box; --exact renders without).
   */
  unsigned controlVariate{ itk::DRRControlVariate::AutomaticFactor };
  bool     controlVariateGiven{ false }; // --control-variate on the command line: refused with --exact, not dropped

  std::string                          inputUnits{ "hu" };
  std::optional<double>                energyKeV;
  std::optional<double>                muWater;
  std::optional<double>                airThreshold;
  std::string                          outputMode; // empty: from the output extension
  std::optional<std::array<double, 2>> window;     // level, width (line-integral units)
  /** --photons I0: quantum noise, I0 photons per pixel with nothing in the beam (DRRQuantumNoiseImageFilter). */
  std::optional<double> photons;

  /** Labels (pbdrrLabels.h): --labels FILE, a label per voxel; --keep-labels / --drop-labels, which attenuate;
   * --label-channels FILE, one line-integral image per label from the same render. */
  std::string           labelsFile;
  std::vector<uint16_t> keepLabels;
  std::vector<uint16_t> dropLabels;
  std::string           labelChannelsOutput;

  /** A polychromatic beam (docs/design.md section 14): --spectrum FILE (keV, fluence) or --kvp KV (Kramers' law,
   * 2.5 mm Al); --materials FILE, the HU -> material table (default DeepDRR's); --jensen-correction. */
  std::string           spectrumFile;
  std::optional<double> kvp;
  std::string           materialsFile;
  bool                  jensenCorrection{ false };

  /** --exact: the kernel whose model the exact projector renders (named by the kernel's ExactReference). */
  std::optional<itk::PointBasedDRREnums::ReconstructionKernel> exact;
  unsigned                                                     raysPerSide{ 1 };

  /** Batches (pbdrrBatch.h): many views of one volume in one run; view k depends only on (seed, k). */
  std::optional<unsigned> angles; // --angles N: a sweep of N views from the view's gantry (SweepStartDegrees())
  std::optional<double>   angleStepDegrees;     // --angle-step DEG: degrees between the sweep's views (default 360 / N)
  std::string             viewsFile;            // --views FILE: one view per line (CSV with a header, pbdrrViewList.h)
  std::string             rtkGeometryFile;      // --rtk-geometry FILE: RTK's projection geometry XML
  std::string             writeRtkGeometry;     // --write-rtk-geometry FILE: the batch's views as RTK's XML
  std::string             manifest;             // --manifest FILE: volumes and their views (CSV, pbdrrManifest.h)
  bool                    stack{ false };       // --stack: one 3D image, a slice per view, instead of numbered files
  std::optional<std::array<unsigned, 2>> shard; // --shard K/N: the views k with k mod N = K
  bool                                   resume{ false };           // --resume: skip views whose output exists
  std::optional<uint64_t>                viewIndex;                 // --view-index K: view K of the batch alone
  bool                                   independentViews{ false }; // --independent-views: new points per view

  bool        quiet{ false };
  std::string listSeries; // --list-series ROOT: list the DICOM series of an export tree and stop
  /** Warnings about options that parse but look like a mistake (e.g. --gantry in radians); printed before the work. */
  std::vector<std::string> warnings;
  bool                     verbose{ false };
  bool                     help{ false };
  bool                     version{ false };
  /** The options the command line gave, by their long names (OptionDeclaration::Name), in its order. */
  std::vector<std::string> given;
};

/** The groups of pbdrr --help (OptionDeclaration::Group), in its order: HelpText() prints each group's heading, then
 * its options in the order of OptionDeclarations(). */
enum class OptionGroup
{
  Geometry,  ///< the view: distances, angles, detector
  Rendering, ///< the estimate: samples, policies, exact projectors
  Physics,   ///< what a voxel attenuates and what a pixel holds
  Batches,   ///< many views or volumes in one run
  Messages   ///< input, other outputs and messages
};

/** One option of pbdrr, declared once (pbdrrOptionDeclarations.cxx, with OptionBuilder): ParseCommandLine() parses it
 * from this declaration, a mode the option does not apply to refuses it (CheckOptionsApply()), HelpText() prints its
 * help, and docs/options.md and the fuzzers' dictionary are made from the declarations (pbdrrOptionPages.h; the tests
 * OptionDeclarations.AreTheOptionsPage and AreTheFuzzDictionary compare them). */
using OptionDeclaration = OptionDeclarationOf<Options, OptionGroup>;

/** Every option of pbdrr, in the order of its help. */
const std::vector<OptionDeclaration> &
OptionDeclarations();

/** True if the command line gave the option called name (its long name). */
bool
IsGiven(const Options & options, const std::string & name);

/** Refuses, with its declaration's message, an option given that mode (one of OptionModes) does not apply to: a single
 * view "NAME, ...: for a batch of views", a batch or a manifest OptionDeclaration::Refusal. Throws UsageError. */
void
CheckOptionsApply(const Options & options, unsigned mode);

/** Parses argv; throws UsageError naming the flag and the bad value. */
Options
ParseCommandLine(const std::vector<std::string> & arguments);

/** Number of samples: a whole number, scientific (1e7) or with a K/M/G suffix (16M = 16 000 000), 1 .. 2^40. */
uint64_t
ParseSampleCount(const std::string & text);

/** pbdrr's default: a stated accuracy, percent (--accuracy), where nothing sets the estimator by hand. */
constexpr double DefaultAccuracyPercent = 0.5;

/** Whether pbdrr's default accuracy (DefaultAccuracyPercent) renders these options: a single view or a batch whose
 * estimator no option sets by hand (none of the rendering group but --seed and --threads), whose output is one
 * line-integral image per view (no --stderr, --label-channels or spectrum: those are the points' own). */
bool
DefaultAccuracyApplies(const Options & options);

/** True if the options ask for a batch of views (--angles, --views, --rtk-geometry, --manifest). */
bool
IsBatch(const Options & options);

/** A finite number, the whole token. */
double
ParseNumber(const std::string & text, const std::string & flag);

/** The name --exact gives the exact projector of kernel's model (`siddon`, `trilinear`), or empty if it has none. */
std::string
ExactReferenceName(itk::PointBasedDRREnums::ReconstructionKernel kernel);

/** pbdrr's help line for a registered policy (a kernel, splat or beam of itkDRRPolicies.h, a sampler of
 * DRRSamplerFactory), by its registered name; empty for a name without one. The library registers each policy once,
 * with its name; the help's words about it are pbdrr's, in one table (pbdrrOptions.cxx). */
std::string
PolicyHelpLine(const std::string & name);

/** The names PolicyHelpLine() has a line for, sorted. */
std::vector<std::string>
PolicyHelpNames();

/** The text of pbdrr --help: the options from OptionDeclarations(), group by group (OptionGroup); the policy lists
 * from the registries (itkDRRPolicies.h, DRRSamplerFactory). */
std::string
HelpText();
} // namespace pbdrr

#endif
