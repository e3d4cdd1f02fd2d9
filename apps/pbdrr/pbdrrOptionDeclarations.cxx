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
// The declarations of pbdrr's options (OptionDeclarations()): one entry per option, from which pbdrrOptions.cxx
// parses, refuses and prints the help; the parsers of their values are in pbdrrOptionValues.cxx.
#include "pbdrrOptions.h"
#include "pbdrrOptionValues.h"
#include "pbdrrMessages.h"
#include "itkDRRControlVariate.h"
#include "itkDRRNumberParser.h"
#include "itkDRRSamplerFactory.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

namespace pbdrr
{
namespace
{
/** The help's list of a policy option's values: a line per registered name, with its help line (PolicyHelpLine()). */
std::string
PolicyChoices(const std::vector<std::string> & names)
{
  size_t width = 0;
  for (const std::string & name : names)
  {
    width = std::max(width, name.size());
  }
  std::ostringstream lines;
  for (const std::string & name : names)
  {
    lines << "                           " << name << std::string(width + 2 - name.size(), ' ') << PolicyHelpLine(name)
          << "\n";
  }
  return lines.str();
}

/** The same for a registry's entries (DRRSamplerFactory::GetEntries()). */
template <typename TEntries>
std::string
PolicyChoices(const TEntries & entries)
{
  std::vector<std::string> names;
  for (const auto & entry : entries)
  {
    names.push_back(entry.Name);
  }
  return PolicyChoices(names);
}

/** The help's list of the values of --exact: the exact projector of each kernel that has one. */
std::string
ExactReferenceLines()
{
  std::string lines;
  for (const std::string & name : itk::PointBasedDRREnums::GetNames<itk::PointBasedDRREnums::ReconstructionKernel>())
  {
    itk::PointBasedDRREnums::ReconstructionKernel kernel{};
    itk::PointBasedDRREnums::FromName(name, kernel);
    const std::string reference = itk::PointBasedDRREnums::GetExactReferenceName(kernel);
    if (!reference.empty())
    {
      lines += "                           " + reference + ": the exact projector of the " + name + " model\n";
    }
  }
  return lines;
}
} // namespace

const std::vector<OptionDeclaration> &
OptionDeclarations()
{
  using Values = std::vector<std::string>;
  // The modes, short: every mode, a single view's only, a batch's (and a manifest's), a batch's only, a manifest's.
  constexpr unsigned all = OptionModes::Every, one = OptionModes::SingleView;
  constexpr unsigned batches = OptionModes::Batch | OptionModes::Manifest, batch = OptionModes::Batch;
  constexpr unsigned manifest = OptionModes::Manifest;
  // The refusals several options share.
  const char * const oneView = "--projection-matrix and --geometry-from give one view: a batch takes its views from "
                               "--angles, --views or --rtk-geometry";
  const char * const polychromatic =
    "--spectrum and --kvp render one view; a batch renders line integrals at one energy";
  using Beams = itk::PointBasedDRREnums::Projection;
  using Kernels = itk::PointBasedDRREnums::ReconstructionKernel;
  using Splats = itk::PointBasedDRREnums::Splat;
  using itk::PointBasedDRREnums;
  const Options      defaults; // the defaults the help states, where Options holds them
  const char * const inRows = "--manifest gives each volume its views and outputs: --angles, --views, --rtk-geometry, "
                              "--view-index and --stack go in its rows, or in a run of one volume";
  static const std::vector<OptionDeclaration> declarations = {
    { "--geometry",
      "",
      1,
      all,
      "",
      OptionGroup::Geometry,
      "FILE",
      "",
      "key value lines: projection, sad, sid, gantry, nrm, vup, isocenter, cols, rows,\n"
      "spacing, offset, mirror (flags below override the file)",
      [](Options & o, const Values & v) { o.geometryFile = v[0]; } },
    { "--sad",
      "",
      1,
      all,
      "",
      OptionGroup::Geometry,
      "MM",
      "1000",
      "source to isocenter distance (default {default})",
      [](Options & o, const Values & v) { o.sad = PositiveLength(v[0], "--sad", "SAD"); } },
    { "--sid",
      "",
      1,
      all,
      "",
      OptionGroup::Geometry,
      "MM",
      "1500",
      "source to detector distance (default {default})",
      [](Options & o, const Values & v) { o.sid = PositiveLength(v[0], "--sid", "SID"); } },
    { "--gantry",
      "",
      1,
      all,
      "",
      OptionGroup::Geometry,
      "DEG",
      "",
      "gantry angle: 0 puts the source on +x (left), 90 on -y (anterior: an AP view)",
      [](Options & o, const Values & v) { o.gantryDegrees = ParseNumber(v[0], "--gantry"); } },
    { "--isocenter",
      "",
      3,
      all,
      "",
      OptionGroup::Geometry,
      "X Y Z",
      "the centre of the volume",
      "mm (default: {default})",
      [](Options & o, const Values & v) { o.isocenter = Numbers<3>(v, "--isocenter"); } },
    { "--nrm",
      "",
      3,
      all,
      "",
      OptionGroup::Geometry,
      "X Y Z",
      "",
      "unit vector from isocenter to source (overrides --gantry)",
      [](Options & o, const Values & v) { o.normal = Numbers<3>(v, "--nrm"); } },
    { "--vup",
      "",
      3,
      all,
      "",
      OptionGroup::Geometry,
      "X Y Z",
      "0 0 1",
      "view up: row 0 is at the +vup edge (default {default})",
      [](Options & o, const Values & v) { o.viewUp = Numbers<3>(v, "--vup"); } },
    { "--size",
      "",
      2,
      all,
      "",
      OptionGroup::Geometry,
      "COLS ROWS",
      "512 512",
      "detector pixels: columns first, then rows (default {default})",
      [](Options & o, const Values & v) {
        o.detectorSize = std::array<double, 2>{ static_cast<double>(WholeNumber(v[0], "--size", 1, 16384)),
                                                static_cast<double>(WholeNumber(v[1], "--size", 1, 16384)) };
      } },
    { "--spacing",
      "",
      2,
      all,
      "",
      OptionGroup::Geometry,
      "DU DV",
      "1.2 1.2",
      "pixel size in mm along columns and rows (default {default})",
      [](Options & o, const Values & v) {
        o.detectorSpacing = std::array<double, 2>{ PositiveLength(v[0], "--spacing", "pixel spacing"),
                                                   PositiveLength(v[1], "--spacing", "pixel spacing") };
      } },
    { "--offset",
      "",
      2,
      all,
      "",
      OptionGroup::Geometry,
      "OU OV",
      "0 0",
      "detector centre offset in mm along columns and rows (default {default})",
      [](Options & o, const Values & v) { o.detectorOffset = Numbers<2>(v, "--offset"); } },
    { "--parallel",
      "",
      0,
      all,
      "",
      OptionGroup::Geometry,
      "",
      "",
      "parallel beam along the normal instead of perspective (--projection parallel)",
      [](Options & o, const Values &) { o.projection = itk::PointBasedDRREnums::Projection::Parallel; } },
    { "--projection",
      "",
      1,
      all,
      "",
      OptionGroup::Geometry,
      "NAME",
      PointBasedDRREnums::GetNames<Beams>().front(),
      "the beam (default {default}):",
      [](Options & o, const Values & v) {
        o.projection = Policy<itk::PointBasedDRREnums::Projection>(v[0], "--projection");
      },
      PolicyChoices(PointBasedDRREnums::GetNames<Beams>()) },
    { "--projection-matrix",
      "",
      1,
      one,
      oneView,
      OptionGroup::Geometry,
      "FILE",
      "",
      "the view from a 3 x 4 projection matrix (12 numbers, rows of 4; room mm -> pixel column,\n"
      "row): with --size, instead of the flags above; --spacing DU names the column pitch",
      [](Options & o, const Values & v) { o.projectionMatrixFile = v[0]; } },
    { "--geometry-from",
      "",
      1,
      one,
      oneView,
      OptionGroup::Geometry,
      "FILE",
      "",
      "the view and pixel grid of a CT localizer (DICOM), from its header: distances, position,\n"
      "orientation, pixel spacing (at the isocenter plane); instead of the flags above",
      [](Options & o, const Values & v) { o.geometryFrom = v[0]; } },
    { "--samples",
      "",
      1,
      all,
      "",
      OptionGroup::Rendering,
      "N",
      std::to_string(itk::DRRPointRenderer::DefaultNumberOfSamples / 1000000) + "M",
      "number of points: 1e7, 16M, 2.5G, 1000000 (default {default})",
      [](Options & o, const Values & v) { o.samples = ParseSampleCount(v[0]); } },
    { "--sampler",
      "",
      1,
      all,
      "",
      OptionGroup::Rendering,
      "NAME",
      defaults.sampler,
      "how points are drawn (default {default}):",
      [](Options & o, const Values & v) { o.sampler = OneOf(v[0], "--sampler", SamplerNames()); },
      PolicyChoices(itk::DRRSamplerFactory::GetEntries()) },
    { "--kernel",
      "",
      1,
      all,
      "",
      OptionGroup::Rendering,
      "NAME",
      PointBasedDRREnums::GetName(defaults.kernel),
      "where in its voxel a point goes (default {default}):",
      [](Options & o, const Values & v) {
        o.kernel = Policy<itk::PointBasedDRREnums::ReconstructionKernel>(v[0], "--kernel");
      },
      PolicyChoices(PointBasedDRREnums::GetNames<Kernels>()) },
    { "--splat",
      "",
      1,
      all,
      "",
      OptionGroup::Rendering,
      "NAME",
      PointBasedDRREnums::GetName(defaults.splat),
      "how a point lands on the detector (default {default}):",
      [](Options & o, const Values & v) { o.splat = Policy<itk::PointBasedDRREnums::Splat>(v[0], "--splat"); },
      PolicyChoices(PointBasedDRREnums::GetNames<Splats>()) },
    { "--strata",
      "",
      1,
      all,
      "",
      OptionGroup::Rendering,
      "R",
      "4 and 16",
      "independent strata for stratified/metropolis (default: {default}): fewer, less error;\n"
      "more, a steadier standard-error image",
      [](Options & o, const Values & v) { o.strata = WholeNumber(v[0], "--strata", 2, 256); } },
    { "--control-variate",
      "",
      1,
      all,
      "",
      OptionGroup::Rendering,
      "F|auto|off",
      "auto",
      "exact coarse image (block means of F^3 voxels, Siddon) plus points for the signed residual\n"
      "only: the same expectation, error about M_r / M of plain sampling; auto picks F for the\n"
      "view (default {default}: on for box-kernel point renders, off where it does not apply)",
      [](Options & o, const Values & v) {
        o.controlVariate = ControlVariateFactor(v[0]);
        o.controlVariateGiven = true;
      } },
    { "--seed",
      "",
      1,
      all,
      "",
      OptionGroup::Rendering,
      "S",
      std::to_string(defaults.seed),
      "random seed (default {default}): the same seed gives the same image on any thread count",
      [](Options & o, const Values & v) {
        const double                          s = ParseNumber(v[0], "--seed");
        if (s < 0 || s != std::floor(s) || s > 9007199254740992.0)
        {
          throw UsageError("--seed expects a whole number from 0 to 2^53, got '" + v[0] + "'");
        }
        o.seed = static_cast<uint64_t>(s);
      } },
    { "--threads",
      "",
      1,
      all,
      "",
      OptionGroup::Rendering,
      "T",
      "all cores",
      "worker threads (default: {default})",
      [](Options & o, const Values & v) { o.threads = WholeNumber(v[0], "--threads", 1, 1024); } },
    { "--stream",
      "",
      1,
      one | batch,
      "--stream reads one volume (a manifest's volumes are read whole)",
      OptionGroup::Rendering,
      "SLABS",
      "",
      "read the CT in SLABS slabs of z planes, one at a time, for a CT larger than\n"
      "memory: the same image (a MetaImage, NRRD or uncompressed NIfTI file; the\n"
      "stratified sampler or --exact siddon)",
      [](Options & o, const Values & v) { o.stream = WholeNumber(v[0], "--stream", 1, 1000000); } },
    { "--memory-budget",
      "",
      1,
      one | batch,
      "--memory-budget applies to one volume (a manifest's volumes are read whole)",
      OptionGroup::Rendering,
      "SIZE",
      "half the memory",
      "stream a CT whose render would hold more than SIZE (e.g. 3G; 0: never)\n"
      "in as many slabs as keep it within (default: {default})",
      [](Options & o, const Values & v) { o.memoryBudget = ParseByteSize(v[0], "--memory-budget"); } },
    { "--paper-count",
      "",
      0,
      all,
      "",
      OptionGroup::Rendering,
      "",
      "",
      "count points unweighted, as the paper does (biased in perspective, and for\n"
      "paper-hybrid biased towards small dense levels)",
      [](Options & o, const Values &) { o.paperCount = true; } },
    { "--exact",
      "",
      1,
      all,
      "",
      OptionGroup::Rendering,
      "NAME",
      "",
      "render with an exact projector instead of points, no noise:",
      [](Options & o, const Values & v) { o.exact = ExactReferenceKernel(v[0]); },
      ExactReferenceLines() },
    { "--ss",
      "",
      1,
      all,
      "",
      OptionGroup::Rendering,
      "K",
      std::to_string(defaults.raysPerSide),
      "with --exact: K x K rays per pixel (default {default}); with --control-variate: K x K\n"
      "antithetic ray pairs per pixel for the coarse image (two replicates of them with --stderr)",
      [](Options & o, const Values & v) { o.raysPerSide = WholeNumber(v[0], "--ss", 1, 64); } },
    { "--input-units",
      "",
      1,
      all,
      "",
      OptionGroup::Physics,
      "hu|mu",
      "",
      "voxels in Hounsfield units (default) or linear attenuation in 1/mm",
      [](Options & o, const Values & v) {
        o.inputUnits = OneOf(v[0], "--input-units", { "hu", "mu" });
      } },
    { "--energy",
      "",
      1,
      all,
      "",
      OptionGroup::Physics,
      "KEV",
      "60 keV",
      "effective energy for mu_water (NIST water table; default {default}: 0.02059 /mm)",
      [](Options & o, const Values & v) { o.energyKeV = ParseNumber(v[0], "--energy"); } },
    { "--mu-water",
      "",
      1,
      all,
      "",
      OptionGroup::Physics,
      "PER_MM",
      "",
      "mu of water directly",
      [](Options & o, const Values & v) { o.muWater = ParseNumber(v[0], "--mu-water"); } },
    { "--air-threshold",
      "",
      1,
      all,
      "",
      OptionGroup::Physics,
      "HU",
      "",
      "voxels below this are air (never sampled)",
      [](Options & o, const Values & v) { o.airThreshold = ParseNumber(v[0], "--air-threshold"); } },
    { "--output-mode",
      "",
      1,
      all,
      "",
      OptionGroup::Physics,
      "line-integral|transmission|gray8|gray16",
      "gray8 for .png, line-integral otherwise",
      "what OUTPUT holds (default: {default})",
      [](Options & o, const Values & v) {
        o.outputMode = OneOf(v[0], "--output-mode", { "line-integral", "transmission", "gray8", "gray16" });
      } },
    { "--window",
      "",
      2,
      all,
      "",
      OptionGroup::Physics,
      "LEVEL WIDTH",
      "percentiles",
      "gray window in line-integral units (default: {default})",
      [](Options & o, const Values & v) { o.window = Numbers<2>(v, "--window"); } },
    { "--photons",
      "",
      1,
      all,
      "",
      OptionGroup::Physics,
      "I0",
      "",
      "quantum noise: each pixel counts Poisson(I0 exp(-L)) photons and reads -ln(N / I0) (no\n"
      "photon: half a photon); I0 per pixel with nothing in the beam; counts seeded by --seed",
      [](Options & o, const Values & v) {
        const double                          photons = ParseNumber(v[0], "--photons");
        if (!(photons > 0.0 && photons <= 1e12))
        {
          throw UsageError("--photons expects photons per pixel in (0, 1e12], got '" + v[0] + "'");
        }
        o.photons = photons;
      } },
    { "--spectrum",
      "",
      1,
      one,
      polychromatic,
      OptionGroup::Physics,
      "FILE",
      "",
      "a polychromatic beam: two columns, energy (keV) and photons per bin; the CT becomes\n"
      "materials and densities (--materials) and every pixel reads -ln(sum_E S(E)\n"
      "exp(-sum_m rho_m L_m mu_m(E)) / sum_E S(E)): beam hardening included",
      [](Options & o, const Values & v) { o.spectrumFile = v[0]; } },
    { "--kvp",
      "",
      1,
      one,
      polychromatic,
      OptionGroup::Physics,
      "KV",
      "",
      "the same with Kramers' spectrum of a KV tube hardened by 2.5 mm Al (Kramers 1923; no\n"
      "characteristic lines)",
      [](Options & o, const Values & v) {
        const double                          kvp = ParseNumber(v[0], "--kvp");
        if (!(kvp >= 20.0 && kvp <= 800.0))
        {
          throw UsageError("--kvp expects a tube voltage from 20 to 800 kV, got '" + v[0] + "'");
        }
        o.kvp = kvp;
      } },
    { "--materials",
      "",
      1,
      all,
      "",
      OptionGroup::Physics,
      "FILE",
      "",
      "the HU -> (material, density) table of --spectrum/--kvp (default DeepDRR's air, soft\n"
      "tissue, bone; docs/design.md section 14)",
      [](Options & o, const Values & v) { o.materialsFile = v[0]; } },
    { "--jensen-correction",
      "",
      0,
      all,
      "",
      OptionGroup::Physics,
      "",
      "",
      "with --spectrum/--kvp: remove the second-order bias of the nonlinear transmission of a\n"
      "noisy estimate, using its covariance",
      [](Options & o, const Values &) { o.jensenCorrection = true; } },
    { "--labels",
      "",
      1,
      all,
      "",
      OptionGroup::Physics,
      "FILE",
      "",
      "a label image (integers 0 to 65535, one per voxel; resampled by nearest neighbour onto the\n"
      "CT's grid if it is not on it)",
      [](Options & o, const Values & v) { o.labelsFile = v[0]; } },
    { "--keep-labels",
      "",
      1,
      all,
      "",
      OptionGroup::Physics,
      "L1,L2",
      "",
      "only the voxels of these labels attenuate (bone only: the bone label)",
      [](Options & o, const Values & v) { o.keepLabels = ParseLabelList(v[0], "--keep-labels"); } },
    { "--drop-labels",
      "",
      1,
      all,
      "",
      OptionGroup::Physics,
      "L1,L2",
      "",
      "the voxels of these labels do not attenuate (the table: its label)",
      [](Options & o, const Values & v) { o.dropLabels = ParseLabelList(v[0], "--drop-labels"); } },
    { "--label-channels",
      "",
      1,
      one,
      "--label-channels writes the channels of one view; a batch renders --keep-labels and --drop-labels, not channels",
      OptionGroup::Physics,
      "FILE",
      "",
      "also write one line-integral image per attenuating label, from the same render, as one\n"
      "multi-component image (.mha, .nrrd, .nii); the labels in its header (PBDRR_ChannelLabels);\n"
      "the channels add up to OUTPUT (rendered without a control variate)",
      [](Options & o, const Values & v) { o.labelChannelsOutput = v[0]; } },
    { "--angles",
      "",
      1,
      batch,
      inRows,
      OptionGroup::Batches,
      "N",
      "",
      "a gantry sweep of N views from --gantry or the --geometry file's (plastimatch's -a)",
      [](Options & o, const Values & v) { o.angles = WholeNumber(v[0], "--angles", 1, 1000000); } },
    { "--angle-step",
      "",
      1,
      batches,
      "",
      OptionGroup::Batches,
      "DEG",
      "360 / N",
      "degrees between the sweep's views (default {default}; plastimatch's -N)",
      [](Options & o, const Values & v) { o.angleStepDegrees = ParseNumber(v[0], "--angle-step"); } },
    { "--views",
      "",
      1,
      batch,
      inRows,
      OptionGroup::Batches,
      "FILE",
      "",
      "one view per line, CSV with a header naming the columns: gantry | nrm_x nrm_y nrm_z,\n"
      "vup_x vup_y vup_z, iso_x iso_y iso_z, sad, sid, offset_u offset_v, the CT's pose tx ty tz\n"
      "rx ry rz (mm, degrees; as pbdrr register's), output (a file name in the -o folder); an\n"
      "empty or absent column keeps the command line's value",
      [](Options & o, const Values & v) { o.viewsFile = v[0]; } },
    { "--rtk-geometry",
      "",
      1,
      batch,
      inRows,
      OptionGroup::Batches,
      "FILE",
      "",
      "RTK's projection geometry XML (rtk::ThreeDCircularProjectionGeometry), with --size and\n"
      "--spacing for the pixels, centred as RTK's tools centre projections",
      [](Options & o, const Values & v) { o.rtkGeometryFile = v[0]; } },
    { "--write-rtk-geometry",
      "",
      1,
      batches,
      "",
      OptionGroup::Batches,
      "FILE",
      "",
      "write the batch's views as RTK's XML",
      [](Options & o, const Values & v) { o.writeRtkGeometry = v[0]; } },
    { "--manifest",
      "",
      1,
      manifest,
      "",
      OptionGroup::Batches,
      "FILE",
      "",
      "many volumes: CSV with a header, columns volume, output (a pattern or a folder), and\n"
      "views (a views file or an RTK XML) or angles [angle_step] [gantry]; paths relative to\n"
      "the manifest; no INPUT, no -o",
      [](Options & o, const Values & v) { o.manifest = v[0]; } },
    { "--output",
      "-o",
      1,
      all,
      "",
      OptionGroup::Batches,
      "PATTERN",
      "",
      "the views' files: a counter %d or %04d is the view's number (view_%04d.mha); a folder\n"
      "(out/) holds view_%04d.mha; each image gets its view beside it (.geometry.txt: the keys\n"
      "and the 3 x 4 matrix)",
      [](Options & o, const Values & v) { o.output = v[0]; } },
    { "--stack",
      "",
      0,
      batch,
      inRows,
      OptionGroup::Batches,
      "",
      "",
      "one 3D image instead, a slice per view (as RTK stores projections), its views beside\n"
      "it in RTK's XML (OUTPUT without extension + .geometry.xml)",
      [](Options & o, const Values &) { o.stack = true; } },
    { "--shard",
      "",
      1,
      batches,
      "",
      OptionGroup::Batches,
      "K/N",
      "",
      "render only the views k with k mod N = K (a manifest counts its views across volumes)",
      [](Options & o, const Values & v) { o.shard = ParseShard(v[0]); } },
    { "--resume",
      "",
      0,
      batches,
      "",
      OptionGroup::Batches,
      "",
      "",
      "skip the views whose image and view are written (files are written under a temporary\n"
      "name and renamed: a killed run leaves no half-written file)",
      [](Options & o, const Values &) { o.resume = true; } },
    { "--view-index",
      "",
      1,
      batch,
      inRows,
      OptionGroup::Batches,
      "K",
      "",
      "render view K of the batch alone: the same image as in any batch",
      [](Options & o, const Values & v) { o.viewIndex = WholeNumber(v[0], "--view-index", 0, 1e9); } },
    { "--independent-views",
      "",
      0,
      batches,
      "",
      OptionGroup::Batches,
      "",
      "",
      "new points for every view (seed from --seed and k) instead of one draw for all: views\n"
      "with independent noise, at the cost of a draw per view",
      [](Options & o, const Values &) { o.independentViews = true; } },
    { "--series",
      "",
      1,
      all,
      "",
      OptionGroup::Messages,
      "UID",
      "",
      "the DICOM series to read from a directory or export of several (default: the largest\n"
      "CT volume; localizers never)",
      [](Options & o, const Values & v) { o.seriesUID = v[0]; } },
    { "--list-series",
      "",
      1,
      all,
      "",
      OptionGroup::Messages,
      "ROOT",
      "",
      "list the DICOM series in ROOT and its folders (kind, size, tilt, description, UID), stop",
      [](Options & o, const Values & v) { o.listSeries = v[0]; } },
    { "--stderr",
      "",
      1,
      one,
      "--stderr writes one view's standard error: it is not available in a batch",
      OptionGroup::Messages,
      "FILE",
      "",
      "per-pixel standard error of the estimate (same units as OUTPUT)",
      [](Options & o, const Values & v) { o.standardErrorOutput = v[0]; } },
    { "--quiet",
      "-q",
      0,
      all,
      "",
      OptionGroup::Messages,
      "",
      "",
      "no progress bar or notes",
      [](Options & o, const Values &) { o.quiet = true; } },
    { "--verbose",
      "-v",
      0,
      all,
      "",
      OptionGroup::Messages,
      "",
      "",
      "geometry, volume, mass, stage times",
      [](Options & o, const Values &) { o.verbose = true; } },
    { "--help",
      "-h",
      0,
      all,
      "",
      OptionGroup::Messages,
      "",
      "",
      "this text",
      [](Options & o, const Values &) { o.help = true; } },
    { "--version",
      "",
      0,
      all,
      "",
      OptionGroup::Messages,
      "",
      "",
      "the version",
      [](Options & o, const Values &) { o.version = true; } },
  };
  return declarations;
}
} // namespace pbdrr
