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
#include "pbdrrBatch.h"
#include "pbdrrBatchAccuracy.h"
#include "pbdrrLabels.h"
#include "pbdrrManifest.h"
#include "pbdrrApplication.h"
#include "pbdrrMessages.h"
#include "pbdrrOutputFiles.h"
#include "pbdrrRegistration.h"
#include "pbdrrView.h"
#include "pbdrrVolumeLoader.h"

#include "itkDRROutputConversion.h"
#include "itkDRRRTKGeometryFileIO.h"
#include "itkImageFileWriter.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <type_traits>
#include <sys/stat.h>
#include <unistd.h>

namespace pbdrr
{
namespace
{
/** The options a batch cannot take, or takes only together; throws UsageError. */
void
CheckBatchOptions(const Options & options)
{
  const int sources =
    (options.angles ? 1 : 0) + (options.viewsFile.empty() ? 0 : 1) + (options.rtkGeometryFile.empty() ? 0 : 1);
  if (sources != 1)
  {
    throw UsageError("give the views one way: --angles, --views or --rtk-geometry");
  }
  if (options.angleStepDegrees && !options.angles)
  {
    throw UsageError("--angle-step is the step of an --angles sweep");
  }
  if (options.angles && options.normal)
  {
    throw UsageError("--angles sweeps the gantry from --gantry: it cannot be combined with --nrm");
  }
  if (!options.rtkGeometryFile.empty())
  {
    std::vector<std::string> flags;
    for (const auto & flag : { std::make_pair(options.gantryDegrees.has_value(), "--gantry"),
                               std::make_pair(options.normal.has_value(), "--nrm"),
                               std::make_pair(options.viewUp.has_value(), "--vup"),
                               std::make_pair(options.isocenter.has_value(), "--isocenter"),
                               std::make_pair(options.sad.has_value(), "--sad"),
                               std::make_pair(options.sid.has_value(), "--sid"),
                               std::make_pair(options.detectorOffset.has_value(), "--offset"),
                               std::make_pair(options.projection.has_value(), "--projection"),
                               std::make_pair(!options.geometryFile.empty(), "--geometry") })
    {
      if (flag.first)
      {
        flags.push_back(flag.second);
      }
    }
    if (!flags.empty())
    {
      throw UsageError("--rtk-geometry gives every view whole (with --size and --spacing for the pixels): it cannot be "
                       "combined with " +
                       JoinWords(flags, ", "));
    }
  }
  if (options.viewIndex && options.shard)
  {
    throw UsageError("--view-index renders one view: it cannot be combined with --shard");
  }
  if (options.stack && (options.shard || options.resume))
  {
    throw UsageError("--stack writes one file for all the views: shards and --resume need numbered files "
                     "(-o view_%04d.mha)");
  }
  if (options.independentViews && options.exact)
  {
    throw UsageError("--independent-views draws new points per view: an --exact render draws none");
  }
  if (HasDetachedHeader(options.output))
  {
    throw UsageError("output " + options.output +
                     ": a batch writes each file whole under a temporary name and "
                     "renames it; a header and its pixels in two files (.mhd, .nhdr) cannot be: use .mha or .nrrd");
  }
  if (options.stack)
  {
    const std::string mode = OutputMode(options);
    if (OutputKind(options.output) != "float" || (mode != "line-integral" && mode != "transmission"))
    {
      throw UsageError("--stack writes a 3D float image (.mha, .nrrd, .nii): line integrals or transmission");
    }
  }
}

/** RTK's pixel grid of the detector of pixels (its size and pitch: the view's own, or for --rtk-geometry the
 * options' view, --size and --spacing over the defaults), centred as RTK's tools centre projections; RTK's image
 * direction (identity) for views whose columns are mirrored, which is how RTK's images lie, and its rows reversed
 * (diag(1, -1)) for views that are not. */
itk::DRRRTKGeometryFileIO::Pointer
MakeRTKGeometryIO(const itk::DRRProjectionGeometry * pixels, bool columnsMirrored)
{
  auto                                             io = itk::DRRRTKGeometryFileIO::New();
  itk::DRRRTKGeometryFileIO::DetectorDirectionType direction;
  direction.SetIdentity();
  direction[1][1] = columnsMirrored ? 1.0 : -1.0;
  io->SetDetectorSize(pixels->GetDetectorSize());
  io->SetDetectorSpacing(pixels->GetDetectorSpacing());
  io->SetDetectorDirection(direction);
  return io;
}

/** The view as RTK's parameters say it: the geometry rebuilt from its RTK parameters (zeros made +0, as the XML writes
 * them), so that a view reads back from RTK's XML, written with 17 digits, to the same bits, and renders the same
 * image. A view RTK cannot express (a localizer) stays as it is. */
itk::DRRProjectionGeometry::Pointer
CanonicalView(const itk::DRRProjectionGeometry::Pointer & geometry)
{
  if (geometry->GetProjection() == itk::PointBasedDRREnums::Projection::Localizer)
  {
    return geometry;
  }
  // The view's own pixel grid: with another, the rebuilt view would have another detector (issue 28: a batch drew
  // the default 512 x 512 pixels of 1.2 mm whatever the geometry file said).
  const auto io = MakeRTKGeometryIO(geometry, geometry->GetColumnsMirrored());
  try
  {
    auto parameters = io->ComputeParameters(geometry);
    for (double * value : { &parameters.GantryAngle,
                            &parameters.OutOfPlaneAngle,
                            &parameters.InPlaneAngle,
                            &parameters.SourceToIsocenterDistance,
                            &parameters.SourceOffsetX,
                            &parameters.SourceOffsetY,
                            &parameters.SourceToDetectorDistance,
                            &parameters.ProjectionOffsetX,
                            &parameters.ProjectionOffsetY })
    {
      *value += 0.0;
    }
    return io->MakeGeometry(parameters);
  }
  catch (const itk::ExceptionObject &)
  {
    return geometry;
  }
}

std::vector<ViewSpec>
ReadViews(const Options & options, std::string & from)
{
  if (options.angles)
  {
    from = "--angles";
    return MakeSweep(*options.angles,
                     SweepStartDegrees(options),
                     options.angleStepDegrees.value_or(360.0 / static_cast<double>(*options.angles)));
  }
  if (!options.viewsFile.empty())
  {
    from = options.viewsFile;
    return ReadViewsFile(options.viewsFile);
  }
  from = options.rtkGeometryFile;
  const auto io = MakeRTKGeometryIO(MakeGeometry(options, nullptr), true);
  io->SetFileName(options.rtkGeometryFile);
  std::vector<ViewSpec> views;
  try
  {
    for (const auto & geometry : io->Read())
    {
      views.emplace_back();
      views.back().Whole = geometry;
    }
  }
  catch (const itk::ExceptionObject & e)
  {
    throw UsageError("--rtk-geometry " + options.rtkGeometryFile + ": " + CleanMessage(e.GetDescription()));
  }
  return views;
}

/** The name of a view's file in an output folder (-o out/) when the views file names none. */
const char * const DefaultViewName = "view_%04d.mha";

/** Each view's output path: its own name in the -o folder (view_%04d.mha if it has none), the pattern's, or the
 * stack. */
std::vector<std::string>
ResolveOutputs(const Options & options, const std::vector<ViewSpec> & views)
{
  std::vector<std::string> outputs(views.size(), options.output);
  if (options.stack)
  {
    if (std::any_of(views.begin(), views.end(), [](const ViewSpec & v) { return !v.Output.empty(); }))
    {
      throw UsageError("--stack writes one file: the views file's output column cannot name the views' files");
    }
    return outputs;
  }
  const bool        folderOnly = EndsWith(options.output, "/") || IsDirectoryPath(options.output);
  const std::string folder =
    folderOnly ? options.output.substr(0, options.output.find_last_not_of('/') + 1) : DirectoryOf(options.output);
  const OutputPattern pattern(folderOnly ? std::string() : options.output);
  for (size_t k = 0; k < views.size(); ++k)
  {
    if (!views[k].Output.empty())
    {
      outputs[k] = (folder.empty() ? "/" : folder + "/") + views[k].Output;
      continue;
    }
    if (folderOnly)
    {
      outputs[k] = OutputPattern((folder.empty() ? "/" : folder + "/") + DefaultViewName).Format(k);
    }
    else if (pattern.HasCounter())
    {
      outputs[k] = pattern.Format(k);
    }
    else if (views.size() > 1 && !options.viewIndex)
    {
      throw UsageError("output " + options.output + " has no view counter for " + std::to_string(views.size()) +
                       " views: give a pattern such as view_%04d.mha (%d, %04d: the view's number), or --stack");
    }
    else
    {
      outputs[k] = pattern.Format(0);
    }
  }
  return outputs;
}

/** Refuses two views writing one file (image or geometry), an extension or folder that cannot be written. */
void
CheckOutputs(const Options & options, const BatchPlan & plan)
{
  std::map<std::string, uint64_t> written;
  std::set<std::string>           checkedFolders;
  for (const uint64_t k : plan.Selected)
  {
    const std::string & output = plan.Outputs[k];
    Options             viewOptions = options;
    viewOptions.output = output;
    OutputMode(viewOptions);
    if (checkedFolders.insert(DirectoryOf(output)).second)
    {
      CheckWritable(output);
    }
  }
  if (options.stack)
  {
    return;
  }
  const bool all = plan.Selected.size() == plan.Views.size() || options.shard;
  for (uint64_t k = 0; k < plan.Views.size(); ++k)
  {
    if (!all && !std::binary_search(plan.Selected.begin(), plan.Selected.end(), k))
    {
      continue;
    }
    for (const std::string & path : { plan.Outputs[k], GeometryPathBeside(plan.Outputs[k]) })
    {
      const auto inserted = written.emplace(path, k);
      if (!inserted.second)
      {
        throw UsageError("two views write " + path + ": " +
                         DescribeView(plan.Views[inserted.first->second], inserted.first->second, plan.ViewsFrom) +
                         " and " + DescribeView(plan.Views[k], k, plan.ViewsFrom));
      }
    }
  }
}

/** Builds every view once, before the load, so that a bad view stops the batch before any rendering. */
void
CheckViews(const Options & options, const BatchPlan & plan)
{
  for (uint64_t k = 0; k < plan.Views.size(); ++k)
  {
    if (plan.Views[k].Whole)
    {
      continue;
    }
    try
    {
      const auto geometry = MakeView(options, plan.Views[k], nullptr);
      if (options.stack && geometry->GetProjection() == itk::PointBasedDRREnums::Projection::Localizer)
      {
        throw UsageError("a stack keeps its views in RTK's XML, which has no localizer beam: give numbered files "
                         "(-o view_%04d.mha), each with its view beside it");
      }
    }
    catch (const itk::ExceptionObject & e)
    {
      throw UsageError(DescribeView(plan.Views[k], k, plan.ViewsFrom) + ": " + CleanMessage(e.GetDescription()));
    }
    catch (const std::exception & e)
    {
      throw UsageError(DescribeView(plan.Views[k], k, plan.ViewsFrom) + ": " + e.what());
    }
  }
}

/** True if the batch writes its views in RTK's XML (--write-rtk-geometry, or a stack's views beside it). */
bool
WritesRTKGeometry(const Options & options)
{
  return options.stack || !options.writeRtkGeometry.empty();
}

/** View k of a batch: MakeView(), the single view's bits, so that view 0 of a batch is the single view of the same
 * options (issue 28); as RTK's parameters say it (CanonicalView()) if the batch writes RTK's XML, so that the XML
 * reads back to the images it was written with. */
itk::DRRProjectionGeometry::Pointer
ViewGeometry(const Options & options, const ViewSpec & view, const itk::ImageBase<3> * volume)
{
  const auto geometry = MakeView(options, view, volume);
  return WritesRTKGeometry(options) ? CanonicalView(geometry) : geometry;
}

/** Every view of the batch in RTK's XML at path (each shard writes the same file, whole): --write-rtk-geometry's file,
 * and the views of a stack beside it. flag names the option in messages. */
void
WriteRTKGeometry(const Options &           options,
                 const BatchPlan &         plan,
                 const itk::ImageBase<3> * volume,
                 const std::string &       path,
                 const std::string &       flag)
{
  itk::DRRRTKGeometryFileIO::ConstGeometryListType geometries;
  for (const ViewSpec & view : plan.Views)
  {
    // The view before CanonicalView(): the writer computes the same RTK parameters from it as CanonicalView() does
    // (from the canonical view it would compute parameters a rounding apart), so the file reads back to its bits.
    geometries.push_back(MakeView(options, view, volume).GetPointer());
  }
  const auto io = MakeRTKGeometryIO(geometries.front(), geometries.front()->GetColumnsMirrored());
  try
  {
    WriteAtomically(path, [&](const std::string & temporary) {
      io->SetFileName(temporary);
      io->Write(geometries);
    });
  }
  catch (const itk::ExceptionObject & e)
  {
    throw std::runtime_error(flag + " " + path + ": " + CleanMessage(e.GetDescription()));
  }
}

/** Where a stack's views go: its stem + ".geometry.xml" (RTK's XML). */
std::string
StackGeometryPath(const std::string & stack)
{
  const std::string text = GeometryPathBeside(stack);
  return text.substr(0, text.size() - 4) + ".xml";
}

/** The stack: one slice per view, the detector's pixel pitch in plane, 1 between slices (as RTK stores projections). */
VolumeType::Pointer
MakeStack(const itk::DRRProjectionGeometry * geometry, size_t views)
{
  auto                 stack = VolumeType::New();
  VolumeType::SizeType size{ { geometry->GetDetectorSize()[0], geometry->GetDetectorSize()[1], views } };
  stack->SetRegions(size);
  VolumeType::SpacingType spacing;
  spacing[0] = geometry->GetDetectorSpacing()[0];
  spacing[1] = geometry->GetDetectorSpacing()[1];
  spacing[2] = 1.0;
  stack->SetSpacing(spacing);
  // Origin and direction as RTK's XML places the pixels (MakeRTKGeometryIO(): centred; rows reversed unless the
  // columns are mirrored), so that RTK reads the stack with the views pbdrr --write-rtk-geometry writes.
  const double              flip = geometry->GetColumnsMirrored() ? 1.0 : -1.0;
  VolumeType::PointType     origin;
  VolumeType::DirectionType direction;
  direction.SetIdentity();
  direction[1][1] = flip;
  origin[0] = -0.5 * (static_cast<double>(size[0]) - 1.0) * spacing[0];
  origin[1] = -flip * 0.5 * (static_cast<double>(size[1]) - 1.0) * spacing[1];
  origin[2] = 0.0;
  stack->SetOrigin(origin);
  stack->SetDirection(direction);
  stack->Allocate(true);
  return stack;
}
} // namespace

uint64_t
ViewSeed(uint64_t seed, uint64_t k)
{
  uint64_t z = seed + 0x9E3779B97F4A7C15ull * (k + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

BatchPlan
PlanBatch(const Options & options, uint64_t shardOffset)
{
  CheckBatchOptions(options);
  BatchPlan plan;
  plan.Views = ReadViews(options, plan.ViewsFrom);
  plan.Outputs = ResolveOutputs(options, plan.Views);
  if (options.viewIndex)
  {
    if (*options.viewIndex >= plan.Views.size())
    {
      throw UsageError("--view-index " + std::to_string(*options.viewIndex) + ": the batch has " +
                       std::to_string(plan.Views.size()) + " views (0 to " + std::to_string(plan.Views.size() - 1) +
                       ")");
    }
    plan.Selected = { *options.viewIndex };
  }
  else
  {
    for (uint64_t k = 0; k < plan.Views.size(); ++k)
    {
      if (!options.shard || (k + shardOffset) % (*options.shard)[1] == (*options.shard)[0])
      {
        plan.Selected.push_back(k);
      }
    }
  }
  CheckOutputs(options, plan);
  if (!options.writeRtkGeometry.empty())
  {
    CheckWritable(options.writeRtkGeometry);
  }
  CheckViews(options, plan);
  if (options.resume)
  {
    std::set<std::string> folders;
    for (const uint64_t k : plan.Selected)
    {
      folders.insert(DirectoryOf(plan.Outputs[k]));
    }
    for (const std::string & folder : folders)
    {
      RemoveStalePartialFiles(folder); // what killed runs left under temporary names
    }
    const auto done = [&](uint64_t k) {
      return FileExists(GeometryPathBeside(plan.Outputs[k])) && IsWholeImageFile(plan.Outputs[k]);
    };
    const auto end = std::remove_if(plan.Selected.begin(), plan.Selected.end(), done);
    plan.Skipped = static_cast<uint64_t>(plan.Selected.end() - end);
    plan.Selected.erase(end, plan.Selected.end());
  }
  return plan;
}

namespace
{
/** The renderer of a batch: the options' own (without a standard error: a batch writes none), with the points kept for
 * every view (unless --independent-views), for volume (its header alone, or null before a DICOM series is read). */
template <typename TVolume>
Renderer<TVolume>
MakeBatchRenderer(const Options & options, const BatchPlan & plan, const TVolume * volume)
{
  const Renderer<TVolume> renderer = MakeRenderer(options, volume);
  if (!volume || options.exact || options.independentViews)
  {
    // Read whole: a DICOM series is, and a streamed batch keeps the points (these would read the CT at every view).
    renderer.Filter->SetMemoryBudget(0);
  }
  if (!renderer.Points)
  {
    return renderer;
  }
  // One draw serves every view: view k's image is then a function of (seed, its view) alone.
  renderer.Points->SetReusePoints(!options.independentViews);
  // Every view of the plan, whichever this run renders: the automatic factor is the same in every run and shard.
  renderer.Points->SetExpectedNumberOfPoses(plan.Views.size());
  return renderer;
}

/** Sets the filter to view k of the plan: its geometry (returned) and its pose. */
template <typename TVolume>
itk::DRRProjectionGeometry::Pointer
SetPlanView(const Options & options, const BatchPlan & plan, uint64_t k, const Renderer<TVolume> & renderer)
{
  const TVolume *  volume = renderer.Filter->GetInput();
  const ViewSpec & view = plan.Views[k];
  auto             geometry = ViewGeometry(options, view, volume);
  renderer.Filter->SetGeometry(geometry);
  renderer.Filter->SetTransform(view.Pose ? MakePoseTransform(volume, *view.Pose)->GetInverseTransform() : nullptr);
  return geometry;
}

/** Fixes `auto`'s factor of the kept points at view 0, whichever views this run renders, so that the split, and so
 * every view's image, is the same in every run and shard. Streamed, the choice at view 0 is set (the volume is not
 * read here); otherwise the first render's. */
template <typename TVolume>
void
FixAutomaticFactor(const Options & options, const BatchPlan & plan, const Renderer<TVolume> & renderer)
{
  if (!renderer.Points || options.independentViews ||
      options.controlVariate != PointFilterType<TVolume>::AutomaticControlVariateFactor)
  {
    return;
  }
  const TVolume * volume = renderer.Filter->GetInput();
  renderer.Filter->SetGeometry(ViewGeometry(options, plan.Views.front(), volume));
  if (renderer.Filter->GetNumberOfSlabs() > 1)
  {
    renderer.Points->SetControlVariateFactor(renderer.Points->ResolveStreamedControlVariateFactor());
  }
  else
  {
    renderer.Points->PrepareSampling();
  }
}

/** Copies view s's image into the stack (made at the first view), in the output mode. */
void
AddToStack(VolumeType::Pointer &              stack,
           const Options &                    options,
           const BatchPlan &                  plan,
           size_t                             s,
           const ProjectionType *             image,
           const itk::DRRProjectionGeometry * geometry)
{
  if (!stack)
  {
    stack = MakeStack(geometry, plan.Selected.size());
  }
  const size_t pixels = image->GetBufferedRegion().GetNumberOfPixels();
  if (pixels * plan.Selected.size() != stack->GetBufferedRegion().GetNumberOfPixels())
  {
    const uint64_t k = plan.Selected[s];
    throw UsageError("--stack needs one detector size for every view; " +
                     DescribeView(plan.Views[k], k, plan.ViewsFrom) + " has another");
  }
  // The library's conversion, as the views' own files use it (WriteOutputs()): a stack's slice is its view's file.
  const itk::DRROutputConversion conversion(OutputMode(options) == "transmission"
                                              ? itk::PointBasedDRREnums::OutputMode::Transmission
                                              : itk::PointBasedDRREnums::OutputMode::LineIntegral,
                                            0.0,
                                            1.0);
  float * slice = stack->GetBufferPointer() + s * pixels;
  for (size_t p = 0; p < pixels; ++p)
  {
    slice[p] = static_cast<float>(conversion.Value(image->GetBufferPointer()[p]));
  }
}

/** pbdrr -v's account of a batch: the load, the first view (with the points' draw), the others, the split. */
template <typename TVolume>
void
PrintBatchTimes(double load, double first, double rest, size_t views, const Renderer<TVolume> & renderer)
{
  const size_t others = views - 1;
  std::cerr << "pbdrr: time: load " << load << " s; the first view (with the points' draw) " << first << " s; "
            << others << " more views " << rest << " s"
            << (others ? ", " + std::to_string(1000.0 * rest / static_cast<double>(others)) + " ms each" : "")
            << std::endl;
  if (renderer.Points)
  {
    if (const itk::DRRControlVariate * split = renderer.Points->GetControlVariate())
    {
      std::cerr << "pbdrr: control variate F " << split->GetFactor() << ", M_r / M "
                << renderer.Points->GetSampler()->GetTotalMass() / split->GetTotalMass() << std::endl;
    }
  }
}
/** Renders the selected views of the plan from a loaded volume (of its own pixel type: int16 HU or float). */
template <typename TVolume>
void
RenderViews(const Options &           options,
            const BatchPlan &         plan,
            BatchProgress &           progress,
            double                    loadSeconds,
            const TVolume *           volume,
            const Renderer<TVolume> & renderer)
{
  renderer.Filter->SetInput(volume);
  // --accuracy over kept points: the estimate of the probes; each view's own otherwise (new points per view).
  double largestError = 0.0;
  if (renderer.Points && renderer.Points->GetChooseEstimator() && !options.independentViews)
  {
    largestError =
      FixAccuracy(renderer, plan.Views.size(), [&](uint64_t k) { SetPlanView(options, plan, k, renderer); });
  }
  else
  {
    FixAutomaticFactor(options, plan, renderer);
  }
  if (!options.writeRtkGeometry.empty())
  {
    WriteRTKGeometry(options, plan, volume, options.writeRtkGeometry, "--write-rtk-geometry");
  }
  const double             renderStart = SteadySeconds();
  double                   firstViewSeconds = 0.0;
  VolumeType::Pointer      stack;
  std::vector<std::string> notes;
  for (size_t s = 0; s < plan.Selected.size(); ++s)
  {
    const uint64_t k = plan.Selected[s];
    const auto     geometry = SetPlanView(options, plan, k, renderer);
    if (renderer.Points && options.independentViews)
    {
      renderer.Points->SetSeed(ViewSeed(options.seed, k));
    }
    renderer.Filter->Update();
    // Quantum noise independent from view to view, and a function of (seed, k) alone.
    const ProjectionType::ConstPointer image =
      AddQuantumNoise(options, renderer.Filter->GetOutput(), ViewSeed(options.seed, k));
    if (options.stack)
    {
      AddToStack(stack, options, plan, s, image, geometry);
    }
    else
    {
      Options viewOptions = options;
      viewOptions.output = plan.Outputs[k];
      // The image, then its view: a view file is there only beside its whole image (both written whole or not at
      // all, WriteAtomically), and --resume counts a view done only with both.
      WriteOutputs(viewOptions, image, nullptr, notes);
      WriteGeometryBeside(plan.Outputs[k], geometry);
    }
    progress.ViewDone();
    firstViewSeconds = s == 0 ? SteadySeconds() - renderStart : firstViewSeconds;
    largestError = renderer.Points ? std::max(largestError, renderer.Points->GetEstimatedError()) : 0.0;
  }
  if (stack)
  {
    // The stack's views beside it, as RTK keeps a projection stack's geometry: before the stack, so that a stack
    // found on disk always has its views.
    WriteRTKGeometry(options, plan, volume, StackGeometryPath(options.output), "--stack's views");
    WriteAtomically(options.output, [&](const std::string & temporary) { itk::WriteImage(stack, temporary); });
  }
  if (options.verbose)
  {
    PrintBatchTimes(
      loadSeconds, firstViewSeconds, SteadySeconds() - renderStart - firstViewSeconds, plan.Selected.size(), renderer);
    if (options.accuracyPercent && renderer.Points)
    {
      PrintBatchAccuracy(options, *renderer.Points, plan.Selected.size(), plan.Views.size(), largestError);
    }
  }
}
} // namespace

namespace
{
/** The batch's renderer built, and asked whether its settings hold, before the load, for the CT's header (headerVolume;
 * null for a DICOM series, whose values decide its pixel type as it is read); then the CT, read whole or, if the
 * filter reads it in slabs, left to the filter. Streamed (--stream, or a CT over the memory budget), the points are
 * drawn slab by slab at the first view and re-projected at every other, so each slab is read for all the views at
 * once. */
template <typename TVolume>
void
LoadAndRenderViews(const Options &      options,
                   const BatchPlan &    plan,
                   BatchProgress &      progress,
                   const LoadedVolume & header,
                   const TVolume *      headerVolume,
                   double               loadStart)
{
  const Renderer<TVolume> renderer = MakeBatchRenderer(options, plan, headerVolume);
  VerifyRenderSettings(options, renderer);
  if (headerVolume)
  {
    renderer.Filter->SetGeometry(ViewGeometry(options, plan.Views.front(), headerVolume)); // the slabs' alignment
  }
  const bool         fromHeader = AnnounceSlabs(options, renderer) > 1 || options.stream > 1;
  const LoadedVolume loaded = LoadVolumeAfterHeader(options, header, fromHeader, {});
  const double       loadSeconds = SteadySeconds() - loadStart;
  for (size_t n = 0; !options.quiet && n < loaded.Notes.size(); ++n)
  {
    std::cerr << "pbdrr: " << loaded.Notes[n] << std::endl;
  }
  loaded.Visit([&](auto * volume) {
    using LoadedType = std::remove_const_t<std::remove_pointer_t<decltype(volume)>>;
    if constexpr (std::is_same_v<LoadedType, TVolume>)
    {
      RenderViews(options, plan, progress, loadSeconds, volume, renderer);
    }
    else
    {
      // A DICOM series of values an int16 does not hold, read as float: the renderer of that type, of the same
      // settings.
      RenderViews(options, plan, progress, loadSeconds, volume, MakeBatchRenderer(options, plan, volume));
    }
  });
}
} // namespace

void
RenderBatch(const Options & options, const BatchPlan & plan, BatchProgress & progress)
{
  const double       loadStart = SteadySeconds();
  const LoadedVolume header = OpenVolumeHeader(options);
  if (header.IsSet())
  {
    header.Visit([&](auto * volume) { LoadAndRenderViews(options, plan, progress, header, volume, loadStart); });
  }
  else
  {
    LoadAndRenderViews<HUVolumeType>(options, plan, progress, header, nullptr, loadStart);
  }
}

void
RunBatch(const Options & options)
{
  // The options a batch, or a manifest, does not apply to (their declarations): --stderr, --label-channels, --kvp, ...
  CheckOptionsApply(options, options.manifest.empty() ? OptionModes::Batch : OptionModes::Manifest);
  CheckLabelOptions(options);
  if (options.stream > 1 && (options.exact || options.independentViews))
  {
    throw UsageError(std::string("--stream in a batch draws the points once, slab by slab, for every view; ") +
                     (options.exact ? "--exact" : "--independent-views") + " would read the CT again at every view");
  }
  if (!options.manifest.empty())
  {
    RunManifest(options);
    return;
  }
  const BatchPlan plan = PlanBatch(options);
  const bool      chatty = !options.quiet;
  if (options.threads > 0)
  {
    itk::MultiThreaderBase::SetGlobalDefaultNumberOfThreads(options.threads);
  }
  if (chatty)
  {
    for (const auto & warning : options.warnings)
    {
      std::cerr << "pbdrr: warning: " << warning << std::endl;
    }
  }
  if (chatty || options.verbose)
  {
    std::cerr << "pbdrr: " << plan.Selected.size() << " of " << plan.Views.size() << " views to render"
              << (plan.Skipped ? " (" + std::to_string(plan.Skipped) + " done before: --resume)" : std::string())
              << std::endl;
  }
  if (plan.Selected.empty())
  {
    return;
  }
  BatchProgress progress(plan.Selected.size(), chatty);
  RenderBatch(options, plan, progress);
  progress.Finish();
}
} // namespace pbdrr
