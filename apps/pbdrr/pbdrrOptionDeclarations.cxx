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
// The declarations of pbdrr's options (OptionDeclarations()): an option in a line or a few, its fields named
// (OptionBuilder, pbdrrOptionTable.h), from which pbdrrOptions.cxx parses, refuses and prints the help, and
// pbdrrOptionPages.cxx writes docs/options.md and the fuzzers' dictionary; the parsers of their values are in
// pbdrrOptionValues.cxx.
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

/** A length in mm (PositiveLength()), called what in its error. */
auto
Length(const char * what)
{
  return [what](const std::string & value, const std::string & flag) { return PositiveLength(value, flag, what); };
}

/** A whole number from lowest to highest (WholeNumber()). */
auto
Whole(double lowest, double highest)
{
  return [lowest, highest](const std::string & value, const std::string & flag) {
    return WholeNumber(value, flag, lowest, highest);
  };
}

/** One of the words allowed (OneOf()). */
auto
Among(std::vector<std::string> allowed)
{
  return [allowed](const std::string & value, const std::string & flag) { return OneOf(value, flag, allowed); };
}

/** --sampler: a registered sampler, by the registry as it is when the option is read. */
std::string
Sampler(const std::string & value, const std::string & flag)
{
  return OneOf(value, flag, SamplerNames());
}

/** --size: columns and rows, whole numbers of pixels. */
std::array<double, 2>
PixelCounts(const std::vector<std::string> & values, const std::string & flag)
{
  return { static_cast<double>(WholeNumber(values[0], flag, 1, 16384)),
           static_cast<double>(WholeNumber(values[1], flag, 1, 16384)) };
}

/** --spacing: the pixel pitch along columns and rows, lengths. */
std::array<double, 2>
PixelSpacings(const std::vector<std::string> & values, const std::string & flag)
{
  return { PositiveLength(values[0], flag, "pixel spacing"), PositiveLength(values[1], flag, "pixel spacing") };
}

/** --seed: a whole number a double holds exactly (0 .. 2^53), as the views' seeds are derived from it. */
uint64_t
Seed(const std::string & value, const std::string & flag)
{
  const double seed = ParseNumber(value, flag);
  if (seed < 0 || seed != std::floor(seed) || seed > 9007199254740992.0)
  {
    throw UsageError(flag + " expects a whole number from 0 to 2^53, got '" + value + "'");
  }
  return static_cast<uint64_t>(seed);
}

/** --photons: I0 per pixel, positive and at most 1e12 (beyond, the Poisson noise is below a float's). */
double
Photons(const std::string & value, const std::string & flag)
{
  const double photons = ParseNumber(value, flag);
  if (!(photons > 0.0 && photons <= 1e12))
  {
    throw UsageError(flag + " expects photons per pixel in (0, 1e12], got '" + value + "'");
  }
  return photons;
}

/** --accuracy: a percent of error to reach, above 0 and at most 100. */
double
Percent(const std::string & value, const std::string & flag)
{
  const double percent = ParseNumber(value, flag);
  if (!(percent > 0.0 && percent <= 100.0))
  {
    throw UsageError(flag + " expects a percent in (0, 100], got '" + value + "'");
  }
  return percent;
}

/** --kvp: a tube voltage Kramers' law is used for, 20 to 800 kV. */
double
TubeVoltage(const std::string & value, const std::string & flag)
{
  const double kvp = ParseNumber(value, flag);
  if (!(kvp >= 20.0 && kvp <= 800.0))
  {
    throw UsageError(flag + " expects a tube voltage from 20 to 800 kV, got '" + value + "'");
  }
  return kvp;
}
} // namespace

const std::vector<OptionDeclaration> &
OptionDeclarations()
{
  using Option = OptionBuilder<Options, OptionGroup>;
  using Values = std::vector<std::string>;
  constexpr OptionGroup Geometry = OptionGroup::Geometry, Rendering = OptionGroup::Rendering;
  constexpr OptionGroup Physics = OptionGroup::Physics, Batches = OptionGroup::Batches;
  constexpr OptionGroup Messages = OptionGroup::Messages;
  // The modes, short: a single view's only, a batch's (and a manifest's), a batch's only, a manifest's (an option
  // without Only() applies to every mode).
  constexpr unsigned one = OptionModes::SingleView, batches = OptionModes::Batch | OptionModes::Manifest;
  constexpr unsigned batch = OptionModes::Batch, manifest = OptionModes::Manifest;
  // The refusals several options share.
  const char * const oneView = "--projection-matrix and --geometry-from give one view: a batch takes its views from "
                               "--angles, --views or --rtk-geometry";
  const char * const polychromatic =
    "--spectrum and --kvp render one view; a batch renders line integrals at one energy";
  const char * const inRows = "--manifest gives each volume its views and outputs: --angles, --views, --rtk-geometry, "
                              "--view-index and --stack go in its rows, or in a run of one volume";
  using Beams = itk::PointBasedDRREnums::Projection;
  using Kernels = itk::PointBasedDRREnums::ReconstructionKernel;
  using Splats = itk::PointBasedDRREnums::Splat;
  using itk::PointBasedDRREnums;
  const Options defaults; // the defaults the help states, where Options holds them
  // Laid out by hand, an option in a line or a few as in RTK's .ggo files: clang-format would put each call of a
  // chain on a line of its own.
  // clang-format off
  static const std::vector<OptionDeclaration> declarations = {
    Option("--geometry").In(Geometry).Takes("FILE").Sets(&Options::geometryFile)
      .Help("key value lines: projection, sad, sid, gantry, nrm, vup, isocenter, cols, rows,\n"
            "spacing, offset, mirror (flags below override the file)"),
    Option("--sad").In(Geometry).Takes("MM").Default("1000").Sets(&Options::sad, Length("SAD"))
      .Help("source to isocenter distance (default {default})"),
    Option("--sid").In(Geometry).Takes("MM").Default("1500").Sets(&Options::sid, Length("SID"))
      .Help("source to detector distance (default {default})"),
    Option("--gantry").In(Geometry).Takes("DEG").Sets(&Options::gantryDegrees, ParseNumber)
      .Help("gantry angle: 0 puts the source on +x (left), 90 on -y (anterior: an AP view)"),
    Option("--isocenter").In(Geometry).Takes("X Y Z").Default("the centre of the volume")
      .Sets(&Options::isocenter, Numbers<3>).Help("mm (default: {default})"),
    Option("--nrm").In(Geometry).Takes("X Y Z").Sets(&Options::normal, Numbers<3>)
      .Help("unit vector from isocenter to source (overrides --gantry)"),
    Option("--vup").In(Geometry).Takes("X Y Z").Default("0 0 1").Sets(&Options::viewUp, Numbers<3>)
      .Help("view up: row 0 is at the +vup edge (default {default})"),
    Option("--size").In(Geometry).Takes("COLS ROWS").Default("512 512").Sets(&Options::detectorSize, PixelCounts)
      .Help("detector pixels: columns first, then rows (default {default})"),
    Option("--spacing").In(Geometry).Takes("DU DV").Default("1.2 1.2").Sets(&Options::detectorSpacing, PixelSpacings)
      .Help("pixel size in mm along columns and rows (default {default})"),
    Option("--offset").In(Geometry).Takes("OU OV").Default("0 0").Sets(&Options::detectorOffset, Numbers<2>)
      .Help("detector centre offset in mm along columns and rows (default {default})"),
    Option("--parallel").In(Geometry).Does([](Options & o, const Values &) { o.projection = Beams::Parallel; })
      .Help("parallel beam along the normal instead of perspective (--projection parallel)"),
    Option("--projection").In(Geometry).Takes("NAME").Default(PointBasedDRREnums::GetNames<Beams>().front())
      .Sets(&Options::projection, Policy<Beams>).Help("the beam (default {default}):")
      .Choices(PolicyChoices(PointBasedDRREnums::GetNames<Beams>())),
    Option("--projection-matrix").In(Geometry).Takes("FILE").Only(one, oneView).Sets(&Options::projectionMatrixFile)
      .Help("the view from a 3 x 4 projection matrix (12 numbers, rows of 4; room mm -> pixel column,\n"
            "row): with --size, instead of the flags above; --spacing DU names the column pitch"),
    Option("--geometry-from").In(Geometry).Takes("FILE").Only(one, oneView).Sets(&Options::geometryFrom)
      .Help("the view and pixel grid of a CT localizer (DICOM), from its header: distances, position,\n"
            "orientation, pixel spacing (at the isocenter plane); instead of the flags above"),
    Option("--samples").In(Rendering).Takes("N").Sets(&Options::samples, ParseSampleCount)
      .Default(std::to_string(itk::DRRPointRenderer::DefaultNumberOfSamples / 1000000) + "M")
      .Help("number of points: 1e7, 16M, 2.5G, 1000000 (default {default} where an option sets the\n"
            "estimator; with none, pbdrr's default is --accuracy's)"),
    Option("--accuracy").In(Rendering).Takes("PCT")
      .Only(one | batch, "--accuracy renders the views of one volume to a stated error (a manifest's volumes "
                         "are rendered as set)")
      .Sets(&Options::accuracyPercent, Percent)
      .Default([] {
        std::ostringstream text;
        text << DefaultAccuracyPercent;
        return text.str();
      }())
      .Help("the error to reach, percent (RMS error over the image's range; default {default} when\n"
            "no rendering option but --seed and --threads is given): the estimator predicted\n"
            "to get there with the least work, exact rays (k x k per pixel), points or a control\n"
            "variate, its points refined until their estimate is at most PCT; with --samples or\n"
            "--control-variate, those points refined (-v lists the candidates and says); a batch\n"
            "chooses at its view 0 for all its views, whose kept points are drawn there"),
    Option("--sampler").In(Rendering).Takes("NAME").Default(defaults.sampler).Sets(&Options::sampler, Sampler)
      .Help("how points are drawn (default {default}):")
      .Choices(PolicyChoices(itk::DRRSamplerFactory::GetEntries())),
    Option("--kernel").In(Rendering).Takes("NAME").Default(PointBasedDRREnums::GetName(defaults.kernel))
      .Sets(&Options::kernel, Policy<Kernels>).Help("where in its voxel a point goes (default {default}):")
      .Choices(PolicyChoices(PointBasedDRREnums::GetNames<Kernels>())),
    Option("--splat").In(Rendering).Takes("NAME").Default(PointBasedDRREnums::GetName(defaults.splat))
      .Sets(&Options::splat, Policy<Splats>).Help("how a point lands on the detector (default {default}):")
      .Choices(PolicyChoices(PointBasedDRREnums::GetNames<Splats>())),
    Option("--strata").In(Rendering).Takes("R").Default("4 and 16").Sets(&Options::strata, Whole(2, 256))
      .Help("independent strata for stratified/metropolis (default: {default}): fewer, less error;\n"
            "more, a steadier standard-error image"),
    Option("--control-variate").In(Rendering).Takes("F|auto|off").Default("auto")
      .Does([](Options & o, const Values & v) {
        o.controlVariate = ControlVariateFactor(v[0]);
        o.controlVariateGiven = true; // given with --exact: refused, not dropped
      })
      .Help("exact coarse image (block means of F^3 voxels, Siddon) plus points for the signed residual\n"
            "only: the same expectation, error about M_r / M of plain sampling; auto picks F for the\n"
            "view (default {default}: on for box-kernel point renders, off where it does not apply)"),
    Option("--seed").In(Rendering).Takes("S").Default(std::to_string(defaults.seed)).Sets(&Options::seed, Seed)
      .Help("random seed (default {default}): the same seed gives the same image on any thread count"),
    Option("--threads").In(Rendering).Takes("T").Default("all cores").Sets(&Options::threads, Whole(1, 1024))
      .Help("worker threads (default: {default})"),
    Option("--stream").In(Rendering).Takes("SLABS").Sets(&Options::stream, Whole(1, 1000000))
      .Only(one | batch, "--stream reads one volume (a manifest's volumes are read whole)")
      .Help("read the CT in SLABS slabs of z planes, one at a time, for a CT larger than\n"
            "memory: the same image (a MetaImage, NRRD or uncompressed NIfTI file; the\n"
            "stratified sampler or --exact siddon)"),
    Option("--memory-budget").In(Rendering).Takes("SIZE").Default("half the memory")
      .Sets(&Options::memoryBudget, ParseByteSize)
      .Only(one | batch, "--memory-budget applies to one volume (a manifest's volumes are read whole)")
      .Help("stream a CT whose render would hold more than SIZE (e.g. 3G; 0: never)\n"
            "in as many slabs as keep it within (default: {default})"),
    Option("--paper-count").In(Rendering).Sets(&Options::paperCount)
      .Help("count points unweighted, as the paper does (biased in perspective, and for\n"
            "paper-hybrid biased towards small dense levels)"),
    Option("--exact").In(Rendering).Takes("NAME").Sets(&Options::exact, ExactReferenceKernel)
      .Help("render with an exact projector instead of points, no noise:").Choices(ExactReferenceLines()),
    Option("--ss").In(Rendering).Takes("K").Default(std::to_string(defaults.raysPerSide))
      .Sets(&Options::raysPerSide, Whole(1, 64))
      .Help("with --exact: K x K rays per pixel (default {default}); with --control-variate: K x K\n"
            "antithetic ray pairs per pixel for the coarse image (two replicates of them with --stderr)"),
    Option("--input-units").In(Physics).Takes("hu|mu").Sets(&Options::inputUnits, Among({ "hu", "mu" }))
      .Help("voxels in Hounsfield units (default) or linear attenuation in 1/mm"),
    Option("--energy").In(Physics).Takes("KEV").Default("60 keV").Sets(&Options::energyKeV, ParseNumber)
      .Help("effective energy for mu_water (NIST water table; default {default}: 0.02059 /mm)"),
    Option("--mu-water").In(Physics).Takes("PER_MM").Sets(&Options::muWater, ParseNumber).Help("mu of water directly"),
    Option("--air-threshold").In(Physics).Takes("HU").Sets(&Options::airThreshold, ParseNumber)
      .Help("voxels below this are air (never sampled)"),
    Option("--output-mode").In(Physics).Takes("line-integral|transmission|gray8|gray16")
      .Sets(&Options::outputMode, Among({ "line-integral", "transmission", "gray8", "gray16" }))
      .Default("gray8 for .png, line-integral otherwise").Help("what OUTPUT holds (default: {default})"),
    Option("--window").In(Physics).Takes("LEVEL WIDTH").Default("percentiles").Sets(&Options::window, Numbers<2>)
      .Help("gray window in line-integral units (default: {default})"),
    Option("--photons").In(Physics).Takes("I0").Sets(&Options::photons, Photons)
      .Help("quantum noise: each pixel counts Poisson(I0 exp(-L)) photons and reads -ln(N / I0) (no\n"
            "photon: half a photon); I0 per pixel with nothing in the beam; counts seeded by --seed"),
    Option("--spectrum").In(Physics).Takes("FILE").Only(one, polychromatic).Sets(&Options::spectrumFile)
      .Help("a polychromatic beam: two columns, energy (keV) and photons per bin; the CT becomes\n"
            "materials and densities (--materials) and every pixel reads -ln(sum_E S(E)\n"
            "exp(-sum_m rho_m L_m mu_m(E)) / sum_E S(E)): beam hardening included"),
    Option("--kvp").In(Physics).Takes("KV").Only(one, polychromatic).Sets(&Options::kvp, TubeVoltage)
      .Help("the same with Kramers' spectrum of a KV tube hardened by 2.5 mm Al (Kramers 1923; no\n"
            "characteristic lines)"),
    Option("--materials").In(Physics).Takes("FILE").Sets(&Options::materialsFile)
      .Help("the HU -> (material, density) table of --spectrum/--kvp (default DeepDRR's air, soft\n"
            "tissue, bone; docs/design.md section 14)"),
    Option("--jensen-correction").In(Physics).Sets(&Options::jensenCorrection)
      .Help("with --spectrum/--kvp: remove the second-order bias of the nonlinear transmission of a\n"
            "noisy estimate, using its covariance"),
    Option("--labels").In(Physics).Takes("FILE").Sets(&Options::labelsFile)
      .Help("a label image (integers 0 to 65535, one per voxel; resampled by nearest neighbour onto the\n"
            "CT's grid if it is not on it)"),
    Option("--keep-labels").In(Physics).Takes("L1,L2").Sets(&Options::keepLabels, ParseLabelList)
      .Help("only the voxels of these labels attenuate (bone only: the bone label)"),
    Option("--drop-labels").In(Physics).Takes("L1,L2").Sets(&Options::dropLabels, ParseLabelList)
      .Help("the voxels of these labels do not attenuate (the table: its label)"),
    Option("--label-channels").In(Physics).Takes("FILE").Sets(&Options::labelChannelsOutput)
      .Only(one, "--label-channels writes the channels of one view; a batch renders --keep-labels and --drop-labels, "
                 "not channels")
      .Help("also write one line-integral image per attenuating label, from the same render, as one\n"
            "multi-component image (.mha, .nrrd, .nii); the labels in its header (PBDRR_ChannelLabels);\n"
            "the channels add up to OUTPUT (rendered without a control variate)"),
    Option("--angles").In(Batches).Takes("N").Only(batch, inRows).Sets(&Options::angles, Whole(1, 1000000))
      .Help("a gantry sweep of N views from --gantry or the --geometry file's (plastimatch's -a)"),
    Option("--angle-step").In(Batches).Takes("DEG").Only(batches).Default("360 / N")
      .Sets(&Options::angleStepDegrees, ParseNumber)
      .Help("degrees between the sweep's views (default {default}; plastimatch's -N)"),
    Option("--views").In(Batches).Takes("FILE").Only(batch, inRows).Sets(&Options::viewsFile)
      .Help("one view per line, CSV with a header naming the columns: gantry | nrm_x nrm_y nrm_z,\n"
            "vup_x vup_y vup_z, iso_x iso_y iso_z, sad, sid, offset_u offset_v, the CT's pose tx ty tz\n"
            "rx ry rz (mm, degrees; as pbdrr register's), output (a file name in the -o folder); an\n"
            "empty or absent column keeps the command line's value"),
    Option("--rtk-geometry").In(Batches).Takes("FILE").Only(batch, inRows).Sets(&Options::rtkGeometryFile)
      .Help("RTK's projection geometry XML (rtk::ThreeDCircularProjectionGeometry), with --size and\n"
            "--spacing for the pixels, centred as RTK's tools centre projections"),
    Option("--write-rtk-geometry").In(Batches).Takes("FILE").Only(batches).Sets(&Options::writeRtkGeometry)
      .Help("write the batch's views as RTK's XML"),
    Option("--manifest").In(Batches).Takes("FILE").Only(manifest).Sets(&Options::manifest)
      .Help("many volumes: CSV with a header, columns volume, output (a pattern or a folder), and\n"
            "views (a views file or an RTK XML) or angles [angle_step] [gantry]; paths relative to\n"
            "the manifest; no INPUT, no -o"),
    Option("--output").Short("-o").In(Batches).Takes("PATTERN").Sets(&Options::output)
      .Help("the views' files: a counter %d or %04d is the view's number (view_%04d.mha); a folder\n"
            "(out/) holds view_%04d.mha; each image gets its view beside it (.geometry.txt: the keys\n"
            "and the 3 x 4 matrix)"),
    Option("--stack").In(Batches).Only(batch, inRows).Sets(&Options::stack)
      .Help("one 3D image instead, a slice per view (as RTK stores projections), its views beside\n"
            "it in RTK's XML (OUTPUT without extension + .geometry.xml)"),
    Option("--shard").In(Batches).Takes("K/N").Only(batches).Sets(&Options::shard, ParseShard)
      .Help("render only the views k with k mod N = K (a manifest counts its views across volumes)"),
    Option("--resume").In(Batches).Only(batches).Sets(&Options::resume)
      .Help("skip the views whose image and view are written (files are written under a temporary\n"
            "name and renamed: a killed run leaves no half-written file)"),
    Option("--view-index").In(Batches).Takes("K").Only(batch, inRows).Sets(&Options::viewIndex, Whole(0, 1e9))
      .Help("render view K of the batch alone: the same image as in any batch"),
    Option("--independent-views").In(Batches).Only(batches).Sets(&Options::independentViews)
      .Help("new points for every view (seed from --seed and k) instead of one draw for all: views\n"
            "with independent noise, at the cost of a draw per view"),
    Option("--series").In(Messages).Takes("UID").Sets(&Options::seriesUID)
      .Help("the DICOM series to read from a directory or export of several (default: the largest\n"
            "CT volume; localizers never)"),
    Option("--list-series").In(Messages).Takes("ROOT").Sets(&Options::listSeries)
      .Help("list the DICOM series in ROOT and its folders (kind, size, tilt, description, UID), stop"),
    Option("--stderr").In(Messages).Takes("FILE").Sets(&Options::standardErrorOutput)
      .Only(one, "--stderr writes one view's standard error: it is not available in a batch")
      .Help("per-pixel standard error of the estimate (same units as OUTPUT)"),
    Option("--quiet").Short("-q").In(Messages).Sets(&Options::quiet).Help("no progress bar or notes"),
    Option("--verbose").Short("-v").In(Messages).Sets(&Options::verbose).Help("geometry, volume, mass, stage times"),
    Option("--help").Short("-h").In(Messages).Sets(&Options::help).Help("this text"),
    Option("--version").In(Messages).Sets(&Options::version).Help("the version"),
  };
  // clang-format on
  return declarations;
}
} // namespace pbdrr
