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
// Issue 28: every option that shapes a view or the estimate gives the same image in every mode of pbdrr (a single
// view, view 0 of --angles 1, a one-row --views file, --view-index 0 of a two-row views file, a one-row manifest), or
// the mode refuses it with a message and writes nothing. Exact renders, and point renders from the same seed, must
// agree bit for bit; point renders from another seed (--independent-views) within the single view's own standard
// error (a z-test).
//
// The cases are a table (ViewModeCases()); ViewModesTable fails for an option declared (pbdrr::OptionDeclarations())
// in no case and not listed as one that shapes no view, and for a case that a mode the option is declared without
// takes. pbdrr itself runs as the command line runs it (PBDRR_EXECUTABLE), on
// a phantom the test writes; --geometry-from reads the localizer MakeTestVolumes writes (PBDRR_TEST_DATA_DIR).
#include "pbdrrImageOutputs.h"
#include "pbdrrOptions.h"

#include "itkDRRPolicies.h"
#include "itkDRRProjectionGeometry.h"
#include "itkDRRProjectionMatrixFileIO.h"
#include "itkDRRSamplerFactory.h"
#include "itkImage.h"
#include "itkImageFileReader.h"
#include "itkImageFileWriter.h"

#include "gtest/gtest.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

#ifndef PBDRR_EXECUTABLE
#error "PBDRR_EXECUTABLE (the path of pbdrr) is not defined"
#endif
#ifndef PBDRR_TEST_DATA_DIR
#error "PBDRR_TEST_DATA_DIR (MakeTestVolumes' folder) is not defined"
#endif

namespace fs = std::filesystem;

namespace
{
/** The modes in which pbdrr builds a view. */
enum class Mode
{
  Single,
  Angles,
  Views,
  ViewIndex,
  Manifest
};
const Mode AllModes[] = { Mode::Single, Mode::Angles, Mode::Views, Mode::ViewIndex, Mode::Manifest };

const char *
ModeName(Mode mode)
{
  switch (mode)
  {
    case Mode::Single:
      return "single view";
    case Mode::Angles:
      return "view 0 of --angles 1";
    case Mode::Views:
      return "a one-row --views file";
    case Mode::ViewIndex:
      return "--view-index 0";
    case Mode::Manifest:
      return "a one-row manifest";
  }
  return "";
}

/** How the images of a case compare: exact renders, and point renders of the same seed, bit for bit; point renders of
 * another seed (--independent-views: view k's points are seeded ViewSeed(seed, k)) by a z-test. */
enum class Render
{
  Exact,
  Points,
  PointsOtherSeed
};

/** One row of the table: options, how they render, and the modes that refuse them (with the message's words). */
struct ViewModeCase
{
  std::string                 Name;
  std::vector<std::string>    Arguments;
  Render                      Kind{ Render::Exact };
  std::map<Mode, std::string> Refusals{};  ///< mode -> a regular expression the message must match
  std::vector<std::string>    Reference{}; ///< the single view to compare with, if the single view refuses Arguments
  std::string                 Extension{ ".mha" };
};

/** A case is shown by its name (GoogleTest prints a parameter's bytes otherwise). */
void
PrintTo(const ViewModeCase & c, std::ostream * os)
{
  *os << c.Name;
}

/** The folder of the test's inputs: the phantom, its labels, geometry, matrix, spectrum and materials files. */
const std::string &
InputFolder()
{
  static const std::string folder = [] {
    const fs::path path = fs::path(::testing::TempDir()) / ("pbdrrViewModes_" + std::to_string(getpid()));
    fs::remove_all(path);
    fs::create_directories(path);
    return path.string();
  }();
  return folder;
}

std::string
Input(const std::string & name)
{
  return InputFolder() + "/" + name;
}

void
WriteText(const std::string & name, const std::string & text)
{
  std::ofstream(Input(name)) << text;
}

/** A small, asymmetric phantom (HU, or mu per mm): a water ellipsoid, a bone block off the axes, air around; and its
 * labels (0 air, 1 water, 2 bone). A view turned, mirrored, shifted or scaled gives another image. */
void
WritePhantom()
{
  using HUType = itk::Image<short, 3>;
  using MuType = itk::Image<float, 3>;
  using LabelType = itk::Image<unsigned short, 3>;
  const HUType::SizeType size{ { 22, 18, 14 } };
  auto                   hu = HUType::New();
  auto                   mu = MuType::New();
  auto                   labels = LabelType::New();
  const double           spacing[3] = { 1.5, 1.25, 2.0 };
  const double           origin[3] = { -15.0, -11.0, -13.0 };
  for (itk::ImageBase<3> * image : std::initializer_list<itk::ImageBase<3> *>{ hu, mu, labels })
  {
    image->SetRegions(size);
    image->SetSpacing(spacing);
    image->SetOrigin(origin);
  }
  hu->Allocate();
  mu->Allocate();
  labels->Allocate();
  for (unsigned z = 0; z < size[2]; ++z)
  {
    for (unsigned y = 0; y < size[1]; ++y)
    {
      for (unsigned x = 0; x < size[0]; ++x)
      {
        const double        u = (x - 10.0) / 9.0, v = (y - 8.0) / 7.0, w = (z - 6.0) / 6.0;
        const bool          water = u * u + v * v + w * w < 1.0;
        const bool          bone = x >= 12 && x < 16 && y >= 4 && y < 7 && z >= 3 && z < 9;
        const itk::Index<3> index{ { x, y, z } };
        hu->SetPixel(index, bone ? 1200 : (water ? 20 : -1000));
        mu->SetPixel(index, bone ? 0.05f : (water ? 0.02f : 0.0f));
        labels->SetPixel(index, bone ? 2 : (water ? 1 : 0));
      }
    }
  }
  itk::WriteImage(hu, Input("phantom.mha"));
  itk::WriteImage(mu, Input("phantom_mu.mha"));
  itk::WriteImage(labels, Input("labels.mha"));
}

/** The files the options read. The geometry file sets every key a batch used to drop (cols, rows, spacing, gantry)
 * and those it kept (sad, sid, offset). */
void
WriteInputs()
{
  WritePhantom();
  WriteText("view.txt", "cols 20\nrows 14\nspacing 2.4 2.0\ngantry 70\nsad 600\nsid 900\noffset 2 -1\n");
  WriteText("mirror.txt", "cols 18\nrows 16\nspacing 2.2 2.2\ngantry 200\nmirror 1\n");
  WriteText("parallel.txt", "projection parallel\ncols 18\nrows 16\nspacing 2 2\ngantry 35\n");
  WriteText("normal.txt", "cols 18\nrows 16\nspacing 2 2\nnrm 0.6 0.8 0\n");
  WriteText("spectrum.txt", "# keV fluence\n40 1\n60 2\n80 1\n");
  WriteText("materials.txt",
            "-inf -800 \"Air, Dry (near sea level)\" 0.001 0.001\n"
            "-800 300 \"Tissue, Soft (ICRP)\" 1.0 1.0\n"
            "300 inf \"Bone, Cortical (ICRP)\" 1.8 1.8\n");
  // The sweep's rows of a one-row views file and of --view-index 0: empty cells keep the command line's view.
  WriteText("one_view.csv", "sad,sid\n,\n");
  WriteText("two_views.csv", "sad,sid\n,\n,\n");
  auto geometry = itk::DRRProjectionGeometry::New();
  geometry->SetGantryAngleInDegrees(20.0);
  geometry->SetDetectorSize({ { 24, 20 } });
  geometry->SetDetectorSpacing(itk::Vector<double, 2>(1.5));
  geometry->VerifyGeometry();
  auto matrix = itk::DRRProjectionMatrixFileIO::New();
  matrix->SetFileName(Input("matrix.txt"));
  matrix->Write(geometry->GetProjectionMatrix());
}

/** The options of pbdrr --help, as CheckEveryOptionTested.cmake finds them: words that open a column, or follow ", ".
 */
std::set<std::string>
HelpOptions()
{
  const std::string     help = pbdrr::HelpText();
  const std::regex      option("(  |, )(--?[a-z][a-z0-9-]*)");
  std::set<std::string> options;
  for (auto it = std::sregex_iterator(help.begin(), help.end(), option); it != std::sregex_iterator(); ++it)
  {
    options.insert((*it)[2].str());
  }
  return options;
}

/** The options that shape no view and no estimate: the modes themselves, the input and the messages. */
const std::set<std::string> &
OptionsThatShapeNoView()
{
  static const std::set<std::string> options = { "-o",         "--output",     "--angles",       "--views",
                                                 "--manifest", "--view-index", "--rtk-geometry", "--series",
                                                 "--quiet",    "-q",           "--verbose",      "-v",
                                                 "--help",     "-h",           "--version",      "--list-series" };
  return options;
}

const std::string BatchOnlyOption = "for a batch of views";
const std::string NoMatrixInABatch = "--projection-matrix and --geometry-from give one view";
const std::string NoSweepOverANormal = "a sweep would replace";
const std::string StreamedExactBatch = "--stream in a batch draws the points once, slab by slab, for every view; "
                                       "--exact would read the CT again at every view";

/** The table: each option that shapes a view or the estimate, in the modes that take it. */
std::vector<ViewModeCase>
ViewModeCases()
{
  const std::vector<std::string> exact = { "--exact", "siddon", "-q" };
  const std::vector<std::string> points = { "--samples", "2e4", "-q" };
  const std::vector<std::string> small = { "--size", "20", "16", "--spacing", "2", "2" };
  const auto                     with = [](std::vector<std::string> a, const std::vector<std::string> & b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
  };
  const std::map<Mode, std::string> batchesRefuseMatrix = { { Mode::Angles, NoMatrixInABatch },
                                                            { Mode::Views, NoMatrixInABatch },
                                                            { Mode::ViewIndex, NoMatrixInABatch },
                                                            { Mode::Manifest, NoMatrixInABatch } };
  const std::map<Mode, std::string> singleRefuses = { { Mode::Single, BatchOnlyOption } };
  const auto                        batchesRefuse = [](const std::string & message) {
    return std::map<Mode, std::string>{
      { Mode::Angles, message }, { Mode::Views, message }, { Mode::ViewIndex, message }, { Mode::Manifest, message }
    };
  };
  std::vector<ViewModeCase> cases = {
    // The view: a geometry file, flags over it, each flag alone.
    { "geometry", with(exact, { "--geometry", Input("view.txt") }) },
    { "geometry_size", with(exact, { "--geometry", Input("view.txt"), "--size", "16", "12" }) },
    { "geometry_spacing", with(exact, { "--geometry", Input("view.txt"), "--spacing", "1.5", "1.5" }) },
    { "geometry_gantry", with(exact, { "--geometry", Input("view.txt"), "--gantry", "30" }) },
    { "geometry_sad_sid", with(exact, { "--geometry", Input("view.txt"), "--sad", "700", "--sid", "1100" }) },
    { "geometry_mirror", with(exact, { "--geometry", Input("mirror.txt") }) },
    { "geometry_parallel", with(exact, { "--geometry", Input("parallel.txt") }) },
    { "geometry_normal",
      with(exact, { "--geometry", Input("normal.txt") }),
      Render::Exact,
      { { Mode::Angles, NoSweepOverANormal }, { Mode::Manifest, NoSweepOverANormal } } },
    { "sad", with(with(exact, small), { "--sad", "700" }) },
    { "sid", with(with(exact, small), { "--sid", "1200" }) },
    { "gantry", with(with(exact, small), { "--gantry", "40" }) },
    { "isocenter", with(with(exact, small), { "--isocenter", "2", "-1", "3" }) },
    { "nrm",
      with(with(exact, small), { "--nrm", "0.6", "-0.8", "0" }),
      Render::Exact,
      { { Mode::Angles, "cannot be combined with --nrm" }, { Mode::Manifest, "cannot be combined with --nrm" } } },
    { "vup", with(with(exact, small), { "--vup", "0.2", "0", "1" }) },
    { "size", with(exact, { "--size", "20", "14" }) },
    { "spacing", with(exact, { "--size", "20", "14", "--spacing", "1.7", "2.1" }) },
    { "offset", with(with(exact, small), { "--offset", "3", "-2" }) },
    { "parallel", with(with(exact, small), { "--parallel" }) },
    { "projection_matrix",
      with(exact, { "--projection-matrix", Input("matrix.txt"), "--size", "24", "20", "--spacing", "1.5", "1.5" }),
      Render::Exact,
      batchesRefuseMatrix },
    { "geometry_from",
      with(exact, { "--geometry-from", std::string(PBDRR_TEST_DATA_DIR) + "/localizer_lateral.dcm" }),
      Render::Exact,
      batchesRefuseMatrix },
    // The physics and the outputs.
    { "input_units", with(with(exact, small), { "--input-units", "mu" }) },
    { "energy", with(with(exact, small), { "--energy", "80" }) },
    { "mu_water", with(with(exact, small), { "--mu-water", "0.018" }) },
    { "air_threshold", with(with(exact, small), { "--air-threshold", "50" }) },
    { "output_mode", with(with(exact, small), { "--output-mode", "transmission" }) },
    { "window", with(with(exact, small), { "--window", "2", "4" }), Render::Exact, {}, {}, ".png" },
    { "photons", with(with(exact, small), { "--photons", "500", "--seed", "3" }) },
    { "labels_keep", with(with(exact, small), { "--labels", Input("labels.mha"), "--keep-labels", "2" }) },
    { "labels_drop", with(with(exact, small), { "--labels", Input("labels.mha"), "--drop-labels", "1" }) },
    { "label_channels",
      with(with(exact, small), { "--labels", Input("labels.mha"), "--label-channels", Input("channels.mha") }),
      Render::Exact,
      batchesRefuse("--label-channels writes the channels of one view") },
    { "kvp", with(with(exact, small), { "--kvp", "90" }), Render::Exact, batchesRefuse("--spectrum and --kvp") },
    { "spectrum",
      with(with(exact, small), { "--spectrum", Input("spectrum.txt") }),
      Render::Exact,
      batchesRefuse("--spectrum and --kvp") },
    { "materials",
      with(with(exact, small), { "--kvp", "90", "--materials", Input("materials.txt") }),
      Render::Exact,
      batchesRefuse("--spectrum and --kvp") },
    { "jensen_correction",
      with(with(points, small), { "--kvp", "90", "--jensen-correction" }),
      Render::Points,
      batchesRefuse("--spectrum and --kvp") },
    { "exact_trilinear", with(small, { "--exact", "trilinear", "-q" }) },
    { "ss", with(with(exact, small), { "--ss", "3" }) },
    // Streamed in slabs: the same bits as the CT read whole (the reference is the view without --stream).
    { "stream",
      with(with(exact, small), { "--stream", "3" }),
      Render::Exact,
      { { Mode::Angles, StreamedExactBatch },
        { Mode::Views, StreamedExactBatch },
        { Mode::ViewIndex, StreamedExactBatch },
        { Mode::Manifest, "--stream reads one volume" } },
      with(exact, small) },
    // The stratified sampler's points streamed: the same points, the same bits (a control variate of F 4, which `auto`
    // never goes below when streaming); a batch draws them slab by slab once and re-projects them at every view.
    { "stream_points",
      with(with(points, small), { "--stream", "2", "--control-variate", "4" }),
      Render::Points,
      { { Mode::Manifest, "--stream reads one volume" } },
      with(with(points, small), { "--control-variate", "4" }) },
    // A budget below the render's bytes streams it unasked: the same bits.
    { "memory_budget",
      with(with(points, small), { "--memory-budget", "2K", "--control-variate", "4" }),
      Render::Points,
      { { Mode::Manifest, "--memory-budget applies to one volume" } },
      with(with(points, small), { "--control-variate", "4" }) },
    { "stderr",
      with(with(points, small), { "--stderr", Input("se_%d.mha") }),
      Render::Points,
      batchesRefuse("--stderr writes one view's standard error") },
    // The estimate of point renders.
    { "samples", with(small, { "--samples", "3e4", "-q" }), Render::Points },
    { "accuracy",
      with(with(points, small), { "--accuracy", "50" }),
      Render::Points,
      { { Mode::Manifest, "--accuracy renders the views of one volume to a stated error" } } },
    { "seed", with(with(points, small), { "--seed", "11" }), Render::Points },
    { "threads", with(with(points, small), { "--threads", "1" }), Render::Points },
    { "paper_count", with(with(points, small), { "--paper-count" }), Render::Points },
    { "control_variate_off", with(with(points, small), { "--control-variate", "off" }), Render::Points },
    { "control_variate_factor", with(with(points, small), { "--control-variate", "4" }), Render::Points },
    { "photons_points", with(with(points, small), { "--photons", "2000" }), Render::Points },
    // The options of a batch alone: the single view refuses them, the batches give the single view's image.
    { "angle_step",
      with(with(exact, small), { "--angle-step", "30" }),
      Render::Exact,
      { { Mode::Single, BatchOnlyOption },
        { Mode::Views, "--angle-step is the step of an --angles sweep" },
        { Mode::ViewIndex, "--angle-step is the step of an --angles sweep" } },
      with(exact, small) },
    { "shard",
      with(with(exact, small), { "--shard", "0/1" }),
      Render::Exact,
      { { Mode::Single, BatchOnlyOption }, { Mode::ViewIndex, "--view-index renders one view" } },
      with(exact, small) },
    { "resume", with(with(exact, small), { "--resume" }), Render::Exact, singleRefuses, with(exact, small) },
    { "write_rtk_geometry",
      with(with(exact, small), { "--write-rtk-geometry", Input("written_%d.xml") }),
      Render::Exact,
      singleRefuses,
      with(exact, small) },
    // New points for view 0 (seeded ViewSeed(seed, 0)): another draw of the same estimate. Without the control
    // variate, whose coarse image's standard error comes from two replicates (too few for a z-test), and with enough
    // points for the error estimate to be steady.
    { "independent_views",
      with(small, { "--samples", "2e5", "--control-variate", "off", "-q", "--independent-views" }),
      Render::PointsOtherSeed,
      singleRefuses,
      with(small, { "--samples", "2e5", "--control-variate", "off", "-q" }) },
    { "stack",
      with(with(exact, small), { "--stack" }),
      Render::Exact,
      { { Mode::Single, BatchOnlyOption }, { Mode::Manifest, "--stack go in its rows" } },
      with(exact, small) },
  };
  // Every registered policy by name (itkDRRPolicies.h, DRRSamplerFactory): a policy added is a case added.
  for (const auto & entry : itk::DRRSamplerFactory::GetEntries())
  {
    std::vector<std::string> arguments = with(with(points, small), { "--sampler", entry.Name });
    if (entry.Name == "stratified")
    {
      arguments.insert(arguments.end(), { "--strata", "8" });
    }
    cases.push_back({ "sampler_" + entry.Name, arguments, Render::Points });
  }
  for (const auto & entry : itk::DRRPolicies::Kernels::GetEntries())
  {
    cases.push_back({ "kernel_" + entry.Name, with(with(points, small), { "--kernel", entry.Name }), Render::Points });
  }
  for (const auto & entry : itk::DRRPolicies::Splats::GetEntries())
  {
    cases.push_back({ "splat_" + entry.Name, with(with(points, small), { "--splat", entry.Name }), Render::Points });
  }
  for (const auto & entry : itk::DRRPolicies::Beams::GetEntries())
  {
    cases.push_back({ "projection_" + entry.Name, with(with(exact, small), { "--projection", entry.Name }) });
  }
  return cases;
}

/** pbdrr arguments to a shell word each. */
std::string
Quoted(const std::string & word)
{
  std::string quoted = "'";
  for (const char c : word)
  {
    quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  }
  return quoted + "'";
}

/** How a run of pbdrr ended. */
struct RunResult
{
  int         ExitCode{ -1 };
  std::string Stderr;
};

RunResult
RunPbdrr(const std::vector<std::string> & arguments, const std::string & errorFile)
{
  std::string command = Quoted(PBDRR_EXECUTABLE);
  for (const std::string & argument : arguments)
  {
    command += " " + Quoted(argument);
  }
  command += " 2>" + Quoted(errorFile) + " >/dev/null";
  const int status = std::system(command.c_str());
  RunResult result;
  result.ExitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream      file(errorFile);
  std::ostringstream text;
  text << file.rdbuf();
  result.Stderr = text.str();
  return result;
}

/** The run of a case in a mode: its arguments and the image it writes. */
struct ModeRun
{
  std::vector<std::string> Arguments;
  std::string              Image;
};

/** Numbers the case's per-run file names (%d in --stderr, --write-rtk-geometry) by the mode, so no two runs share one.
 */
std::vector<std::string>
Numbered(const std::vector<std::string> & arguments, Mode mode)
{
  std::vector<std::string> numbered = arguments;
  for (std::string & argument : numbered)
  {
    const size_t at = argument.find("%d");
    if (at != std::string::npos)
    {
      argument.replace(at, 2, std::to_string(static_cast<int>(mode)));
    }
  }
  return numbered;
}

ModeRun
MakeModeRun(const std::string & folder, const ViewModeCase & c, Mode mode, const std::vector<std::string> & arguments)
{
  const std::string        stem = folder + "/" + c.Name + "_" + std::to_string(static_cast<int>(mode));
  const bool               mu = std::find(arguments.begin(), arguments.end(), "--input-units") != arguments.end();
  const std::string        phantom = Input(mu ? "phantom_mu.mha" : "phantom.mha");
  std::vector<std::string> head;
  ModeRun                  run;
  switch (mode)
  {
    case Mode::Single:
      head = { phantom, "-o", stem + c.Extension };
      run.Image = stem + c.Extension;
      break;
    case Mode::Angles:
      head = { phantom, "-o", stem + "_%d" + c.Extension, "--angles", "1" };
      run.Image = stem + "_0" + c.Extension;
      break;
    case Mode::Views:
      head = { phantom, "-o", stem + "_%d" + c.Extension, "--views", Input("one_view.csv") };
      run.Image = stem + "_0" + c.Extension;
      break;
    case Mode::ViewIndex:
      head = { phantom, "-o", stem + c.Extension, "--views", Input("two_views.csv"), "--view-index", "0" };
      run.Image = stem + c.Extension;
      break;
    case Mode::Manifest:
    {
      const std::string manifest = stem + ".csv";
      std::ofstream(manifest) << "volume,output,angles\n" << phantom << "," << stem << "_%d" << c.Extension << ",1\n";
      head = { "--manifest", manifest };
      run.Image = stem + "_0" + c.Extension;
      break;
    }
  }
  if (mode != Mode::Manifest && std::find(arguments.begin(), arguments.end(), "--stack") != arguments.end())
  {
    // A stack is one file: its slice 0 is view 0 (a 3D image of one slice, read below as the 2D view).
    head[2] = stem + c.Extension;
    run.Image = stem + c.Extension;
  }
  run.Arguments = head;
  const auto numbered = Numbered(arguments, mode);
  run.Arguments.insert(run.Arguments.end(), numbered.begin(), numbered.end());
  return run;
}

using ViewImage = itk::Image<float, 3>;

/** An image as floats (a 2D view read as a 3D image of one slice; a stack of one view likewise). */
ViewImage::Pointer
ReadView(const std::string & path)
{
  return itk::ReadImage<ViewImage>(path);
}

/** The lines of a view written beside an image but the first, which names the image. */
std::vector<std::string>
ViewLines(const std::string & path)
{
  std::ifstream            file(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(file, line);)
  {
    lines.push_back(line);
  }
  if (!lines.empty())
  {
    lines.erase(lines.begin());
  }
  return lines;
}

std::string
ShowArguments(const std::vector<std::string> & arguments)
{
  std::string shown = "pbdrr";
  for (const auto & argument : arguments)
  {
    shown += " " + argument;
  }
  return shown;
}

/** The sums of the image's values over blocks of 4 x 4 pixels (or of their squares: squares). */
std::vector<double>
BlockSums(const ViewImage * image, const float * values, bool squares)
{
  const auto          size = image->GetLargestPossibleRegion().GetSize();
  const size_t        columns = (size[0] + 3) / 4, rows = (size[1] + 3) / 4;
  std::vector<double> sums(columns * rows, 0.0);
  for (size_t r = 0; r < size[1]; ++r)
  {
    for (size_t c = 0; c < size[0]; ++c)
    {
      const double value = values[r * size[0] + c];
      sums[(r / 4) * columns + c / 4] += squares ? value * value : value;
    }
  }
  return sums;
}

/** The same pixel grid (size, spacing, origin) and:
 * - Exact: the same values, bit for bit;
 * - Points (the same seed): the same points, so the same values but for the rounding of the single-precision positions
 *   in which a batch keeps its points (PointBasedDRRImageFilter::SetReusePoints()): |a - b| at most 1e-5 of the
 *   image's largest value, where the Monte Carlo noise is a thousand times that;
 * - PointsOtherSeed: within the noise, by a z-test on the sums over blocks of 4 x 4 pixels (a pixel's own error,
 *   estimated from its few points, is too unsteady to divide by), the variance 2 se^2 of two independent renders from
 *   the single view's standard error: no block's |z| beyond 5 and a mean z^2 (about 1) below 3. */
::testing::AssertionResult
SameView(const ViewImage * reference,
         const ViewImage * standardError,
         const ViewImage * image,
         Render            kind,
         bool              pixelsOnly = false)
{
  const auto size = reference->GetLargestPossibleRegion().GetSize();
  if (image->GetLargestPossibleRegion().GetSize() != size)
  {
    return ::testing::AssertionFailure() << "size " << image->GetLargestPossibleRegion().GetSize()
                                         << ", the single view's " << size;
  }
  for (unsigned d = 0; d < 2 && !pixelsOnly; ++d)
  {
    if (std::abs(image->GetSpacing()[d] - reference->GetSpacing()[d]) > 1e-9 * reference->GetSpacing()[d] ||
        std::abs(image->GetOrigin()[d] - reference->GetOrigin()[d]) > 1e-6)
    {
      return ::testing::AssertionFailure()
             << "spacing " << image->GetSpacing() << " origin " << image->GetOrigin() << ", the single view's "
             << reference->GetSpacing() << " " << reference->GetOrigin();
    }
  }
  const size_t  pixels = reference->GetBufferedRegion().GetNumberOfPixels();
  const float * a = reference->GetBufferPointer();
  const float * b = image->GetBufferPointer();
  if (std::memcmp(a, b, pixels * sizeof(float)) == 0)
  {
    return ::testing::AssertionSuccess();
  }
  if (kind == Render::Exact)
  {
    size_t differ = 0;
    for (size_t p = 0; p < pixels; ++p)
    {
      differ += std::memcmp(a + p, b + p, sizeof(float)) != 0;
    }
    return ::testing::AssertionFailure() << differ << " of " << pixels << " pixels differ (bit for bit expected)";
  }
  double largest = 0.0, largestDifference = 0.0;
  for (size_t p = 0; p < pixels; ++p)
  {
    largest = std::max(largest, std::abs(static_cast<double>(a[p])));
    largestDifference = std::max(largestDifference, std::abs(static_cast<double>(a[p]) - b[p]));
  }
  if (kind == Render::Points)
  {
    if (largestDifference > 1e-5 * largest)
    {
      return ::testing::AssertionFailure() << "not the same points: a pixel differs by " << largestDifference
                                           << " (the image reaches " << largest << ")";
    }
    return ::testing::AssertionSuccess();
  }
  if (!standardError)
  {
    return ::testing::AssertionFailure() << "no standard error for the z-test";
  }
  const std::vector<double> first = BlockSums(reference, a, false);
  const std::vector<double> second = BlockSums(reference, b, false);
  const std::vector<double> variance = BlockSums(reference, standardError->GetBufferPointer(), true);
  double                    sumZ2 = 0.0, maxZ = 0.0;
  size_t                    counted = 0;
  for (size_t k = 0; k < first.size(); ++k)
  {
    if (variance[k] > 0.0)
    {
      const double z = (first[k] - second[k]) / std::sqrt(2.0 * variance[k]);
      sumZ2 += z * z;
      maxZ = std::max(maxZ, std::abs(z));
      ++counted;
    }
    else if (first[k] != second[k])
    {
      return ::testing::AssertionFailure() << "block " << k << " differs where the single view has no error";
    }
  }
  const double meanZ2 = counted ? sumZ2 / static_cast<double>(counted) : 0.0;
  if (maxZ > 5.0 || meanZ2 > 3.0)
  {
    return ::testing::AssertionFailure() << "beyond the Monte Carlo noise: max |z| " << maxZ << ", mean z^2 " << meanZ2
                                         << " over " << counted << " blocks of 4 x 4 pixels";
  }
  return ::testing::AssertionSuccess();
}

class ViewModes : public ::testing::TestWithParam<ViewModeCase>
{
public:
  static void
  SetUpTestSuite()
  {
    WriteInputs();
  }

  static void
  TearDownTestSuite()
  {
    if (::testing::UnitTest::GetInstance()->failed_test_count() == 0)
    {
      fs::remove_all(InputFolder()); // kept after a failure, to look at
    }
  }
};

TEST_P(ViewModes, EveryModeGivesTheSingleViewsImageOrRefuses)
{
  const ViewModeCase & c = GetParam();
  const std::string    folder = InputFolder() + "/" + c.Name;
  fs::create_directories(folder);

  // The reference: the single view of the options (or of Reference, for an option the single view refuses), with
  // its standard error for a point render.
  const bool               ownReference = c.Reference.empty();
  std::vector<std::string> referenceArguments = ownReference ? c.Arguments : c.Reference;
  const bool               wantsError = c.Kind == Render::PointsOtherSeed;
  const std::string        standardErrorPath = folder + "/reference_se.mha";
  if (wantsError)
  {
    referenceArguments.insert(referenceArguments.end(), { "--stderr", standardErrorPath });
  }
  ViewModeCase referenceCase = c;
  referenceCase.Name = "reference";
  const ModeRun   reference = MakeModeRun(folder, referenceCase, Mode::Single, referenceArguments);
  const RunResult referenceResult = RunPbdrr(reference.Arguments, folder + "/reference.err");
  ASSERT_EQ(referenceResult.ExitCode, 0) << ShowArguments(reference.Arguments) << "\n" << referenceResult.Stderr;
  const auto referenceImage = ReadView(reference.Image);
  const auto standardError = wantsError ? ReadView(standardErrorPath) : ViewImage::Pointer();

  for (const Mode mode : AllModes)
  {
    const ModeRun run = MakeModeRun(folder, c, mode, c.Arguments);
    std::remove(run.Image.c_str());
    const RunResult   result = RunPbdrr(run.Arguments, folder + "/" + std::to_string(static_cast<int>(mode)) + ".err");
    const auto        refusal = c.Refusals.find(mode);
    const std::string shown = std::string(ModeName(mode)) + ": " + ShowArguments(run.Arguments);
    if (refusal != c.Refusals.end())
    {
      EXPECT_EQ(result.ExitCode, 2) << shown << "\n" << result.Stderr;
      EXPECT_TRUE(std::regex_search(result.Stderr, std::regex("pbdrr: error: .*" + refusal->second)))
        << shown << ": the message must say why (" << refusal->second << "), got: " << result.Stderr;
      EXPECT_FALSE(fs::exists(run.Image)) << shown << ": a refused run must write nothing";
      continue;
    }
    ASSERT_EQ(result.ExitCode, 0) << shown << "\n" << result.Stderr;
    if (mode == Mode::Single && ownReference)
    {
      // The reference itself, run again without --stderr: the same bits.
      EXPECT_TRUE(SameView(referenceImage, nullptr, ReadView(run.Image), Render::Exact)) << shown;
      continue;
    }
    // A stack lays its slices out as RTK's projections (its own origin and direction): its pixels are the view's.
    const bool stack = std::find(c.Arguments.begin(), c.Arguments.end(), "--stack") != c.Arguments.end();
    EXPECT_TRUE(SameView(referenceImage, standardError, ReadView(run.Image), c.Kind, stack))
      << shown << "\nagainst " << ShowArguments(reference.Arguments);
    // The view written beside the image, too: the same keys and matrix, to the last digit (a batch that writes RTK's
    // XML renders its views as RTK's parameters say them, a rounding apart: docs/design.md section 11).
    const bool rtk =
      stack || std::find(c.Arguments.begin(), c.Arguments.end(), "--write-rtk-geometry") != c.Arguments.end();
    if (!rtk)
    {
      EXPECT_EQ(ViewLines(pbdrr::GeometryPathBeside(run.Image)), ViewLines(pbdrr::GeometryPathBeside(reference.Image)))
        << shown << ": the view beside the image";
    }
  }
}

std::string
CaseName(const ::testing::TestParamInfo<ViewModeCase> & info)
{
  std::string name = info.param.Name;
  std::replace_if(
    name.begin(), name.end(), [](char c) { return !std::isalnum(static_cast<unsigned char>(c)); }, '_');
  return name;
}

INSTANTIATE_TEST_SUITE_P(Options, ViewModes, ::testing::ValuesIn(ViewModeCases()), CaseName);

// The table covers pbdrr: an option declared (OptionDeclarations()) in no case, and not one that shapes no view,
// fails here; so does a case whose option a mode should refuse, by its declaration, but which the case expects the
// mode to take.
TEST(ViewModesTable, EveryDeclaredOptionHasACaseAndEveryModeItLacksRefusesIt)
{
  std::set<std::string> covered = OptionsThatShapeNoView();
  for (const ViewModeCase & c : ViewModeCases())
  {
    for (const std::string & argument : c.Arguments)
    {
      if (argument.rfind("-", 0) == 0)
      {
        covered.insert(argument);
      }
    }
  }
  const std::pair<Mode, unsigned> modeBits[] = { { Mode::Single, pbdrr::OptionModes::SingleView },
                                                 { Mode::Angles, pbdrr::OptionModes::Batch },
                                                 { Mode::Views, pbdrr::OptionModes::Batch },
                                                 { Mode::ViewIndex, pbdrr::OptionModes::Batch },
                                                 { Mode::Manifest, pbdrr::OptionModes::Manifest } };
  for (const pbdrr::OptionDeclaration & declaration : pbdrr::OptionDeclarations())
  {
    EXPECT_TRUE(covered.count(declaration.Name))
      << declaration.Name << " is declared but in no case of ViewModeCases() (nor in OptionsThatShapeNoView()): give "
      << "it a case";
    for (const ViewModeCase & c : ViewModeCases())
    {
      if (std::find(c.Arguments.begin(), c.Arguments.end(), declaration.Name) == c.Arguments.end())
      {
        continue;
      }
      for (const auto & mode : modeBits)
      {
        EXPECT_TRUE((declaration.Modes & mode.second) || c.Refusals.count(mode.first))
          << c.Name << ": " << declaration.Name << " is declared without the mode of " << ModeName(mode.first)
          << ", which must refuse it";
      }
    }
  }
  // And --help lists no option that is not declared.
  std::set<std::string> declared;
  for (const pbdrr::OptionDeclaration & declaration : pbdrr::OptionDeclarations())
  {
    declared.insert(declaration.Name);
    declared.insert(declaration.Short);
  }
  for (const std::string & option : HelpOptions())
  {
    EXPECT_TRUE(declared.count(option)) << option << " is in pbdrr --help but not declared (OptionDeclarations())";
  }
}
} // namespace

// One window and conversion rule (issue 40, item 2): a PNG (gray8 and gray16, the automatic window and a given one)
// holds the gray levels the library's conversion gives the same render, as pbdrr writes them into a float image with
// --output-mode gray8 / gray16 (DRROutputConversion, its automatic window ComputeAutomaticWindow()), pixel for pixel.
TEST(ViewModesTable, APngIsTheLibrarysGrayConversion)
{
  WriteInputs();
  const std::string folder = Input("gray");
  fs::create_directories(folder);
  const std::vector<std::vector<std::string>> windows = { {}, { "--window", "6", "9" } };
  for (const std::string mode : { "gray8", "gray16" })
  {
    for (const auto & window : windows)
    {
      std::vector<std::string> common = { Input("phantom.mha"), "--size", "160",    "120",
                                          "--samples",          "1e6",    "--seed", "4",
                                          "--output-mode",      mode,     "-q" };
      common.insert(common.end(), window.begin(), window.end());
      const std::string name = folder + "/" + mode + (window.empty() ? "_auto" : "_window");
      auto              png = common;
      png.insert(png.end(), { "-o", name + ".png" });
      auto mha = common;
      mha.insert(mha.end(), { "-o", name + ".mha" });
      ASSERT_EQ(RunPbdrr(png, name + ".png.err").ExitCode, 0) << ShowArguments(png);
      ASSERT_EQ(RunPbdrr(mha, name + ".mha.err").ExitCode, 0) << ShowArguments(mha);
      const auto   picture = ReadView(name + ".png");
      const auto   levels = ReadView(name + ".mha");
      const size_t pixels = levels->GetBufferedRegion().GetNumberOfPixels();
      ASSERT_EQ(picture->GetBufferedRegion().GetNumberOfPixels(), pixels);
      size_t differ = 0, clipped = 0;
      for (size_t p = 0; p < pixels; ++p)
      {
        differ += picture->GetBufferPointer()[p] != levels->GetBufferPointer()[p];
        clipped += levels->GetBufferPointer()[p] == 0.0f;
      }
      EXPECT_EQ(differ, 0u) << name << ": the PNG is another picture than the library's conversion";
      EXPECT_GT(clipped, 0u) << name << ": the window clips no pixel: the test shows nothing";
    }
  }
}
