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
#include "pbdrrApplication.h"
#include "pbdrrBatch.h"
#include "pbdrrDicomLocalizerGeometry.h"
#include "pbdrrMessages.h"
#include "pbdrrOutputFiles.h"
#include "pbdrrRegistration.h"
#include "pbdrrVolumeLoader.h"

#include "itkCommand.h"
#include "itkDRRPolicies.h"
#include "itkDRRProjectionGeometryFileIO.h"
#include "itkDRRQuantumNoiseImageFilter.h"
#include "itkDRRProjectionMatrixFileIO.h"
#include "itkExactDRRImageFilter.h"
#include "itkDRROutputConversion.h"
#include "itkDRRSamplerFactory.h"
#include "itkImageFileWriter.h"
#include "itkPointBasedDRRImageFilter.h"
#include "itkVersion.h"

#include <cerrno>
#include <cstring>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <cstdio>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <sys/stat.h>
#include <unistd.h>

namespace pbdrr
{
namespace
{
using GrayType = itk::Image<unsigned char, 2>;
using Gray16Type = itk::Image<unsigned short, 2>;
using OutputModeEnum = itk::PointBasedDRREnums::OutputMode;
using Clock = std::chrono::steady_clock;

double
SecondsSince(Clock::time_point start)
{
  return std::chrono::duration<double>(Clock::now() - start).count();
}

} // namespace

/** The output kind an extension stands for: "png" (gray levels) or "float". Throws for unknown extensions. */
std::string
OutputKind(const std::string & path)
{
  const std::string lower = Lowercase(path);
  for (const char * e : { ".mha", ".mhd", ".nrrd", ".nhdr", ".nii", ".nii.gz", ".tif", ".tiff" })
  {
    if (EndsWith(lower, e))
    {
      return "float";
    }
  }
  if (EndsWith(lower, ".png"))
  {
    return "png";
  }
  throw UsageError("output " + path + ": unknown extension (use .mha, .nrrd, .nii, .nii.gz, .tif or .png)");
}

/** Checks up front, without creating anything, that a file can be written at path, so that a long render does not
 * end in a write error and a failed run leaves no empty file behind. */
void
CheckWritable(const std::string & path)
{
  struct stat status;
  if (stat(path.c_str(), &status) == 0)
  {
    if (S_ISDIR(status.st_mode))
    {
      throw std::runtime_error("cannot write output " + path + ": it is a directory");
    }
    if (access(path.c_str(), W_OK) != 0)
    {
      throw std::runtime_error("cannot write output " + path + ": " + std::strerror(errno));
    }
    return;
  }
  const size_t      slash = path.find_last_of('/');
  const std::string directory = slash == std::string::npos ? "." : (slash == 0 ? "/" : path.substr(0, slash));
  if (stat(directory.c_str(), &status) != 0 || !S_ISDIR(status.st_mode))
  {
    throw std::runtime_error("cannot write output " + path + ": directory " + directory + " does not exist");
  }
  if (access(directory.c_str(), W_OK) != 0)
  {
    throw std::runtime_error("cannot write output " + path + ": " + std::strerror(errno));
  }
}

namespace
{

/** The flags that set a view by parts, which a whole view (--projection-matrix, --geometry-from) replaces. */
std::vector<std::string>
ViewFlagsGiven(const Options & options)
{
  std::vector<std::string>            given;
  const std::pair<bool, const char *> flags[] = { { !options.geometryFile.empty(), "--geometry" },
                                                  { options.sad.has_value(), "--sad" },
                                                  { options.sid.has_value(), "--sid" },
                                                  { options.gantryDegrees.has_value(), "--gantry" },
                                                  { options.isocenter.has_value(), "--isocenter" },
                                                  { options.normal.has_value(), "--nrm" },
                                                  { options.viewUp.has_value(), "--vup" },
                                                  { options.detectorOffset.has_value(), "--offset" },
                                                  { options.projection.has_value(), "--projection/--parallel" } };
  for (const auto & flag : flags)
  {
    if (flag.first)
    {
      given.push_back(flag.second);
    }
  }
  return given;
}

/** The view of a projection matrix file: --size is required (a matrix does not say the detector's size), --spacing DU
 * names the column pitch (the matrix gives the rows' pitch relative to it). */
itk::DRRProjectionGeometry::Pointer
MakeGeometryFromMatrix(const Options & options)
{
  if (!options.detectorSize)
  {
    throw UsageError(
      "--projection-matrix needs --size COLS ROWS: a projection matrix does not say the detector's size");
  }
  auto matrixReader = itk::DRRProjectionMatrixFileIO::New();
  matrixReader->SetFileName(options.projectionMatrixFile);
  const auto matrix = matrixReader->Read();
  auto       geometry = itk::DRRProjectionGeometry::New();
  if (options.detectorSpacing)
  {
    itk::Vector<double, 2> spacing;
    spacing[0] = (*options.detectorSpacing)[0];
    spacing[1] = (*options.detectorSpacing)[1];
    geometry->SetDetectorSpacing(spacing);
  }
  geometry->SetProjectionMatrix(matrix,
                                { { static_cast<itk::SizeValueType>((*options.detectorSize)[0]),
                                    static_cast<itk::SizeValueType>((*options.detectorSize)[1]) } });
  geometry->VerifyGeometry();
  return geometry;
}

} // namespace

itk::DRRProjectionGeometry::Pointer
MakeGeometry(const Options & options, const VolumeType * volume)
{
  const bool matrix = !options.projectionMatrixFile.empty();
  const bool localizer = !options.geometryFrom.empty();
  if (matrix || localizer)
  {
    const std::string        whole = matrix ? "--projection-matrix" : "--geometry-from";
    std::vector<std::string> conflicting = ViewFlagsGiven(options);
    if (matrix && localizer)
    {
      conflicting.push_back("--geometry-from");
    }
    if (localizer && (options.detectorSize || options.detectorSpacing))
    {
      conflicting.push_back("--size/--spacing");
    }
    if (!conflicting.empty())
    {
      throw UsageError(whole + " gives the whole view: it cannot be combined with " + JoinWords(conflicting, ", "));
    }
    return matrix ? MakeGeometryFromMatrix(options) : ReadLocalizerView(options.geometryFrom).Geometry;
  }
  auto geometry = itk::DRRProjectionGeometry::New();
  geometry->SetDetectorSize({ { 512, 512 } });
  geometry->SetDetectorSpacing(itk::Vector<double, 2>(1.2));
  // Default isocenter: the centre of the volume's bounding box (voxel centres); the room origin before the load.
  if (volume)
  {
    geometry->SetIsocenterToImageCenter(volume);
  }
  if (!options.geometryFile.empty())
  {
    geometry->ReadGeometryFile(options.geometryFile);
  }
  auto point = [](const std::array<double, 3> & a) {
    itk::Point<double, 3> p;
    std::copy(a.begin(), a.end(), p.Begin());
    return p;
  };
  auto vector3 = [](const std::array<double, 3> & a) {
    itk::Vector<double, 3> v;
    std::copy(a.begin(), a.end(), v.Begin());
    return v;
  };
  auto vector2 = [](const std::array<double, 2> & a) {
    itk::Vector<double, 2> v;
    v[0] = a[0];
    v[1] = a[1];
    return v;
  };
  if (options.projection)
  {
    geometry->SetProjection(*options.projection);
  }
  if (options.sad)
  {
    geometry->SetSourceToIsocenterDistance(*options.sad);
  }
  if (options.sid)
  {
    geometry->SetSourceToDetectorDistance(*options.sid);
  }
  if (options.gantryDegrees)
  {
    geometry->SetGantryAngleInDegrees(*options.gantryDegrees);
  }
  if (options.normal)
  {
    geometry->SetNormal(vector3(*options.normal));
  }
  if (options.viewUp)
  {
    geometry->SetViewUp(vector3(*options.viewUp));
  }
  if (options.isocenter)
  {
    geometry->SetIsocenter(point(*options.isocenter));
  }
  if (options.detectorSize)
  {
    geometry->SetDetectorSize({ { static_cast<itk::SizeValueType>((*options.detectorSize)[0]),
                                  static_cast<itk::SizeValueType>((*options.detectorSize)[1]) } });
  }
  if (options.detectorSpacing)
  {
    geometry->SetDetectorSpacing(vector2(*options.detectorSpacing));
  }
  if (options.detectorOffset)
  {
    geometry->SetDetectorOffset(vector2(*options.detectorOffset));
  }
  geometry->VerifyGeometry();
  if (itk::DRRPolicies::Beams::Visit(geometry->GetProjection(), [](auto beam) { return decltype(beam)::HasSource; }) &&
      !(geometry->GetSourceToDetectorDistance() > geometry->GetSourceToIsocenterDistance()))
  {
    // The render keeps what lies between the source and the detector: the volume would be behind it, the image empty.
    std::ostringstream message;
    message << "the detector lies between the source and the isocenter (SID " << geometry->GetSourceToDetectorDistance()
            << " mm <= SAD " << geometry->GetSourceToIsocenterDistance()
            << " mm), so the volume is behind it: give --sid larger than --sad";
    throw UsageError(message.str());
  }
  return geometry;
}

itk::DRRTransferFunction::Pointer
MakeTransferFunction(const Options & options)
{
  auto transfer = itk::DRRTransferFunction::New();
  if (options.inputUnits == "mu")
  {
    transfer->SetMode(itk::PointBasedDRREnums::TransferFunction::Identity);
  }
  if (options.energyKeV)
  {
    transfer->SetEffectiveEnergyInKeV(*options.energyKeV);
  }
  if (options.muWater)
  {
    transfer->SetMuWaterPerMillimeter(*options.muWater);
  }
  if (options.airThreshold)
  {
    transfer->SetAirThreshold(*options.airThreshold);
  }
  return transfer;
}

namespace
{
/** Progress on a terminal only (never into a file or a pipe), shown once the work has run for half a second: a bar
 * with the time left for a render, a count of files for a load. */
class ProgressBar
{
public:
  explicit ProgressBar(bool enabled) : m_Enabled(enabled && isatty(fileno(stderr))), m_Start(Clock::now()) {}
  ~ProgressBar() { this->Finish(); }

  void
  Show(float progress)
  {
    if (!this->Due())
    {
      return;
    }
    if (progress + 0.01f < m_LastProgress)
    {
      m_PhaseStart = Clock::now(); // a new stage of the render (the control variate's coarse image, then the points)
    }
    m_LastProgress = progress;
    const int width = 40;
    const int filled = static_cast<int>(progress * width + 0.5f);
    std::fprintf(stderr,
                 "\r[%s%s] %3d%%%s",
                 std::string(filled, '=').c_str(),
                 std::string(width - filled, ' ').c_str(),
                 static_cast<int>(progress * 100.0f + 0.5f),
                 TimeLeft(progress, SecondsSince(m_PhaseStart)).c_str());
    std::fflush(stderr);
    m_Shown = true;
  }

  /** "what done / total", e.g. the files of a DICOM series read so far. */
  void
  ShowCount(const char * what, size_t done, size_t total)
  {
    if (!this->Due())
    {
      return;
    }
    std::fprintf(stderr, "\r%s %zu / %zu", what, done, total);
    std::fflush(stderr);
    m_Shown = true;
  }

  void
  Finish()
  {
    if (m_Shown)
    {
      std::fprintf(stderr, "\r%80s\r", "");
      std::fflush(stderr);
      m_Shown = false;
    }
  }

private:
  /** On a terminal, once the work has run for half a second. */
  bool
  Due() const
  {
    return m_Enabled && SecondsSince(m_Start) >= 0.5;
  }

  /** ", about 12 s left": the elapsed time scaled by what is left, once 2% is done (blank before, and at the end). */
  static std::string
  TimeLeft(float progress, double elapsedSeconds)
  {
    if (!(progress >= 0.02f) || progress >= 1.0f)
    {
      return "                    ";
    }
    const auto left = static_cast<long>(std::lround(elapsedSeconds * (1.0 - progress) / progress));
    char       text[64];
    if (left < 1)
    {
      std::snprintf(text, sizeof(text), ", under a second left  ");
    }
    else if (left < 60)
    {
      std::snprintf(text, sizeof(text), ", about %ld s left     ", left);
    }
    else
    {
      std::snprintf(text, sizeof(text), ", about %ld min %02ld s left", left / 60, left % 60);
    }
    return text;
  }

  bool              m_Enabled;
  bool              m_Shown{ false };
  Clock::time_point m_Start;
  Clock::time_point m_PhaseStart{ m_Start };
  float             m_LastProgress{ 0.0f };
};

std::string
Describe(const VolumeType * volume)
{
  const auto         region = volume->GetLargestPossibleRegion();
  std::ostringstream s;
  s << "size " << region.GetSize()[0] << " x " << region.GetSize()[1] << " x " << region.GetSize()[2] << ", spacing "
    << volume->GetSpacing()[0] << " x " << volume->GetSpacing()[1] << " x " << volume->GetSpacing()[2] << " mm, origin "
    << volume->GetOrigin() << " mm, direction [";
  for (unsigned int r = 0; r < 3; ++r)
  {
    s << (r ? "; " : "") << volume->GetDirection()[r][0] << " " << volume->GetDirection()[r][1] << " "
      << volume->GetDirection()[r][2];
  }
  const float * values = volume->GetBufferPointer();
  const auto    range = std::minmax_element(values, values + region.GetNumberOfPixels());
  if (range.first == values + region.GetNumberOfPixels())
  {
    s << "], no values (empty)"; // nothing to dereference: the checks that refuse an empty volume come later
    return s.str();
  }
  s << "], values " << *range.first << " .. " << *range.second;
  return s.str();
}

std::string
DescribeGeometry(const itk::DRRProjectionGeometry * g)
{
  std::ostringstream s;
  const auto         number = [](double value) { return RoundedForDisplay(value); };
  s << itk::DRRPolicies::Beams::GetName(g->GetProjection()) << ", SAD " << number(g->GetSourceToIsocenterDistance())
    << " mm, SID " << number(g->GetSourceToDetectorDistance()) << " mm, isocenter " << FormatTriple(g->GetIsocenter())
    << ", nrm " << FormatTriple(g->GetNormal()) << ", vup " << FormatTriple(g->GetViewUp()) << ", detector "
    << g->GetDetectorSize()[0] << " cols x " << g->GetDetectorSize()[1] << " rows at "
    << number(g->GetDetectorSpacing()[0]) << " x " << number(g->GetDetectorSpacing()[1]) << " mm, offset "
    << number(g->GetDetectorOffset()[0]) << " " << number(g->GetDetectorOffset()[1]) << " mm; source "
    << FormatTriple(g->GetSourcePosition()) << ", columns along " << FormatTriple(g->GetColumnDirection())
    << ", rows along " << FormatTriple(g->GetRowDirection());
  return s.str();
}

/** Writes an image at path through a temporary name (WriteAtomically), or directly for a format of two files. */
template <typename TImage>
void
WriteImageAtomically(const TImage * image, const std::string & path)
{
  if (HasDetachedHeader(path))
  {
    itk::WriteImage(image, path);
    return;
  }
  WriteAtomically(path, [image](const std::string & temporary) { itk::WriteImage(image, temporary); });
}

/** Gray-level window: the user's, or the 0.5 and 99.5 percentiles of the line integrals. */
void
ChooseWindow(const Options & options, const ProjectionType * image, double & level, double & width)
{
  if (options.window)
  {
    level = (*options.window)[0];
    width = (*options.window)[1];
    if (!(width > 0.0))
    {
      throw UsageError("--window width must be positive, got " + std::to_string(width));
    }
    return;
  }
  std::vector<float> values(image->GetBufferPointer(),
                            image->GetBufferPointer() + image->GetBufferedRegion().GetNumberOfPixels());
  std::sort(values.begin(), values.end());
  const double low = values[static_cast<size_t>(0.005 * (values.size() - 1))];
  const double high = values[static_cast<size_t>(0.995 * (values.size() - 1))];
  width = std::max(high - low, 1e-6);
  level = low + 0.5 * width;
}

template <typename TGray>
void
WriteGray(const ProjectionType * lineIntegral, const itk::DRROutputConversion & conversion, const std::string & path)
{
  auto gray = TGray::New();
  gray->CopyInformation(lineIntegral);
  gray->SetRegions(lineIntegral->GetLargestPossibleRegion());
  gray->Allocate();
  const float * in = lineIntegral->GetBufferPointer();
  auto *        out = gray->GetBufferPointer();
  for (size_t p = 0; p < gray->GetBufferedRegion().GetNumberOfPixels(); ++p)
  {
    out[p] = static_cast<typename TGray::PixelType>(conversion.Value(in[p]));
  }
  WriteImageAtomically(gray.GetPointer(), path);
}

} // namespace

std::string
GeometryPathBeside(const std::string & output)
{
  std::string  stem = output;
  const size_t slash = stem.find_last_of('/');
  const size_t dot = stem.find_last_of('.');
  if (EndsWith(Lowercase(output), ".nii.gz"))
  {
    stem.resize(stem.size() - 7);
  }
  else if (dot != std::string::npos && (slash == std::string::npos || dot > slash))
  {
    stem.resize(dot);
  }
  return stem + ".geometry.txt";
}

/** The geometry file `--geometry` reads (every key, bit for bit) and, as comments, the 3 x 4 projection matrix, so that
 * another tool can reproduce the view. */
std::string
WriteGeometryBeside(const std::string & output, const itk::DRRProjectionGeometry * geometry)
{
  const std::string  path = GeometryPathBeside(output);
  std::ostringstream text;
  // The image's file name, not its path: the same view written into another folder (a shard's) is the same file.
  text << "# the view of " << output.substr(output.find_last_of('/') + 1) << " (pbdrr --geometry reads it)\n";
  if (geometry->HasProjectionMatrix())
  {
    // The matrix in the format --projection-matrix reads, commented out (remove the '#   ' to use it).
    text << "# 3 x 4 projection matrix: room point X (mm) -> pixel (column, row) = (p0 / p2, p1 / p2), p = P [X; 1]\n";
    std::stringstream matrix;
    itk::DRRProjectionMatrixFileIO::WriteToStream(matrix, geometry->GetProjectionMatrix());
    for (std::string line; std::getline(matrix, line);)
    {
      text << "#   " << line << "\n";
    }
  }
  else
  {
    text << "# a " << itk::DRRPolicies::Beams::GetName(geometry->GetProjection())
         << " beam has no 3 x 4 projection matrix: the view is the keys below\n";
  }
  itk::DRRProjectionGeometryFileIO::WriteToStream(text, geometry);
  WriteAtomically(path, [&](const std::string & temporary) {
    std::ofstream file(temporary);
    file << text.str();
    if (!file.flush())
    {
      throw std::runtime_error("cannot write the view beside the image: " + path);
    }
  });
  return path;
}

/** The output mode: --output-mode, or the output extension's own; refuses a mode the extension cannot hold. */
std::string
OutputMode(const Options & options)
{
  const std::string kind = OutputKind(options.output);
  const std::string mode = !options.outputMode.empty() ? options.outputMode : kind == "png" ? "gray8" : "line-integral";
  if (kind == "png" && mode != "gray8" && mode != "gray16")
  {
    throw UsageError("a .png output holds gray levels: use --output-mode gray8 or gray16, or a float format (.mha)");
  }
  return mode;
}

/** Writes the line-integral image (and its standard error) as the output path and mode say. */
void
WriteOutputs(const Options &            options,
             const ProjectionType *     lineIntegral,
             const ProjectionType *     standardError,
             std::vector<std::string> & notes)
{
  const std::string kind = OutputKind(options.output);
  const std::string mode = OutputMode(options);
  double            level = 0.0, width = 1.0;
  if (mode == "gray8" || mode == "gray16")
  {
    ChooseWindow(options, lineIntegral, level, width);
    notes.push_back("gray window: level " + std::to_string(level) + ", width " + std::to_string(width) +
                    " (line-integral units)");
  }
  const OutputModeEnum           outputMode = mode == "transmission" ? OutputModeEnum::Transmission
                                              : mode == "gray8"      ? OutputModeEnum::Gray8
                                              : mode == "gray16"     ? OutputModeEnum::Gray16
                                                                     : OutputModeEnum::LineIntegral;
  const itk::DRROutputConversion conversion(outputMode, level - 0.5 * width, width);
  auto                           write = [&](const ProjectionType * image, const std::string & path, bool isError) {
    if (outputMode == OutputModeEnum::LineIntegral)
    {
      WriteImageAtomically(image, path);
      return;
    }
    auto converted = ProjectionType::New();
    converted->CopyInformation(image);
    converted->SetRegions(image->GetLargestPossibleRegion());
    converted->Allocate();
    const float * in = image->GetBufferPointer();
    const float * l = lineIntegral->GetBufferPointer();
    float *       out = converted->GetBufferPointer();
    for (size_t p = 0; p < converted->GetBufferedRegion().GetNumberOfPixels(); ++p)
    {
      // A standard error goes through the mode by the delta method: times d(value) / dL at the pixel's L.
      out[p] = static_cast<float>(isError ? conversion.Slope(l[p]) * in[p] : conversion.Value(in[p]));
    }
    WriteImageAtomically(converted.GetPointer(), path);
  };
  if (kind == "png")
  {
    if (outputMode == OutputModeEnum::Gray8)
    {
      WriteGray<GrayType>(lineIntegral, conversion, options.output);
    }
    else
    {
      WriteGray<Gray16Type>(lineIntegral, conversion, options.output);
    }
  }
  else
  {
    write(lineIntegral, options.output, false);
  }
  if (standardError)
  {
    write(standardError, options.standardErrorOutput, true);
  }
}
Renderer
MakeRenderer(const Options & options, const VolumeType * volume)
{
  Renderer renderer;
  if (!options.exact)
  {
    auto pointBased = PointFilterType::New();
    pointBased->SetNumberOfSamples(options.samples);
    pointBased->SetSeed(options.seed);
    pointBased->SetNumberOfStrata(options.strata);
    pointBased->SetReconstructionKernel(options.kernel);
    pointBased->SetSplat(options.splat);
    pointBased->SetPointWeighting(options.paperCount ? itk::PointBasedDRREnums::PointWeighting::PaperCount
                                                     : itk::PointBasedDRREnums::PointWeighting::Unbiased);
    pointBased->SetSampler(itk::DRRSamplerFactory::Create(options.sampler, options.paperCount));
    pointBased->SetControlVariateFactor(options.controlVariate);
    pointBased->SetControlVariateRaysPerSide(options.raysPerSide);
    renderer.Points = pointBased;
    renderer.Filter = pointBased.GetPointer();
  }
  else
  {
    auto exact = itk::ExactDRRImageFilter<VolumeType, ProjectionType>::New();
    exact->SetReconstructionKernel(*options.exact);
    exact->SetRaysPerPixelSide(options.raysPerSide);
    renderer.Filter = exact.GetPointer();
  }
  renderer.Filter->SetInput(volume);
  renderer.Filter->SetTransferFunction(MakeTransferFunction(options));
  if (options.threads > 0)
  {
    renderer.Filter->SetNumberOfWorkUnits(options.threads);
  }
  return renderer;
}

ProjectionType::ConstPointer
AddQuantumNoise(const Options & options, const ProjectionType * image, uint64_t seed)
{
  if (!options.photons)
  {
    return image;
  }
  auto noise = itk::DRRQuantumNoiseImageFilter<ProjectionType>::New();
  noise->SetInput(image);
  noise->SetNumberOfPhotons(*options.photons);
  noise->SetSeed(seed);
  noise->Update();
  return noise->GetOutput();
}

std::string
VersionText()
{
  return "pbdrr (PointBasedDRR) 0.1.0, ITK " + std::string(itk::Version::GetITKVersion());
}

namespace
{
/** Refuses the options of a batch (--shard, --stack, ...) in a run of one view. */
void
CheckSingleViewOptions(const Options & options)
{
  std::vector<std::string> flags;
  for (const auto & flag : { std::make_pair(options.angleStepDegrees.has_value(), "--angle-step"),
                             std::make_pair(options.shard.has_value(), "--shard"),
                             std::make_pair(options.resume, "--resume"),
                             std::make_pair(options.viewIndex.has_value(), "--view-index"),
                             std::make_pair(options.stack, "--stack"),
                             std::make_pair(options.independentViews, "--independent-views"),
                             std::make_pair(!options.writeRtkGeometry.empty(), "--write-rtk-geometry") })
  {
    if (flag.first)
    {
      flags.push_back(flag.second);
    }
  }
  if (!flags.empty())
  {
    throw UsageError(JoinWords(flags, ", ") +
                     ": for a batch of views (--angles, --views, --rtk-geometry or --manifest)");
  }
}
} // namespace

void
Run(const Options & options)
{
  if (IsBatch(options))
  {
    RunBatch(options);
    return;
  }
  CheckSingleViewOptions(options);
  const bool                                  chatty = !options.quiet;
  std::vector<std::string>                    notes;
  std::vector<std::pair<std::string, double>> stages;
  OutputMode(options); // refuse unknown extensions, and modes they cannot hold, before any work
  if (chatty)
  {
    for (const auto & warning : options.warnings)
    {
      std::cerr << "pbdrr: warning: " << warning << std::endl;
    }
  }
  if (!options.standardErrorOutput.empty())
  {
    if (OutputKind(options.standardErrorOutput) == "png")
    {
      throw UsageError("--stderr needs a float format (.mha, .nrrd, .nii, .tif), not .png");
    }
    if (options.exact)
    {
      throw UsageError("--stderr: an exact render has no statistical error");
    }
    if (options.photons)
    {
      throw UsageError("--stderr is the point estimate's error; with --photons the image has quantum noise on top: "
                       "give one of them");
    }
  }
  struct stat inputStatus;
  if (!options.seriesUID.empty() && stat(options.input.c_str(), &inputStatus) == 0 && !S_ISDIR(inputStatus.st_mode))
  {
    throw UsageError("--series selects a series in a DICOM directory; " + options.input + " is a file");
  }
  CheckWritable(options.output);
  if (!options.standardErrorOutput.empty())
  {
    CheckWritable(options.standardErrorOutput);
  }
  if (options.threads > 0)
  {
    itk::MultiThreaderBase::SetGlobalDefaultNumberOfThreads(options.threads);
  }

  MakeGeometry(options, nullptr); // the view's checks (geometry file, SID against SAD) before the load

  auto               start = Clock::now();
  ProgressBar        loadProgress(chatty);
  const LoadedVolume loaded = LoadVolume(options.input, options.seriesUID, [&](size_t done, size_t total) {
    loadProgress.ShowCount("reading DICOM files", done, total);
  });
  loadProgress.Finish();
  stages.emplace_back("load", SecondsSince(start));
  for (const auto & note : loaded.Notes)
  {
    if (chatty)
    {
      std::cerr << "pbdrr: " << note << std::endl;
    }
  }
  const auto geometry = MakeGeometry(options, loaded.Image);
  if (!options.projectionMatrixFile.empty())
  {
    CheckDetectorBeyondVolume(geometry, loaded.Image, 0.0, "--projection-matrix (--spacing DU)");
  }
  if (options.verbose)
  {
    std::cerr << "pbdrr: input: " << loaded.Description << "\npbdrr: volume: " << Describe(loaded.Image)
              << "\npbdrr: geometry: " << DescribeGeometry(geometry) << std::endl;
  }

  const Renderer    renderer = MakeRenderer(options, loaded.Image);
  BaseFilterType *  filter = renderer.Filter;
  PointFilterType * pointBased = renderer.Points;
  filter->SetGeometry(geometry);

  start = Clock::now();
  if (pointBased)
  {
    pointBased->PrepareSampling();
  }
  else
  {
    filter->GetAttenuationVolume();
  }
  stages.emplace_back("preprocess", SecondsSince(start));

  ProgressBar progress(chatty);
  auto        command = itk::CStyleCommand::New();
  command->SetClientData(&progress);
  command->SetCallback([](itk::Object * caller, const itk::EventObject &, void * data) {
    static_cast<ProgressBar *>(data)->Show(static_cast<itk::ProcessObject *>(caller)->GetProgress());
  });
  filter->AddObserver(itk::ProgressEvent(), command);
  start = Clock::now();
  filter->Update();
  progress.Finish();
  stages.emplace_back(!options.exact ? "sample+project" : "exact projection", SecondsSince(start));
  const ProjectionType * image = filter->GetOutput();
  if (chatty && std::all_of(image->GetBufferPointer(),
                            image->GetBufferPointer() + image->GetBufferedRegion().GetNumberOfPixels(),
                            [](float v) { return v == 0.0f; }))
  {
    std::cerr << "pbdrr: warning: the image is empty: the volume is all air or does not project onto the detector "
                 "(check --isocenter, --gantry/--nrm, --offset and --size)"
              << std::endl;
  }

  start = Clock::now();
  const ProjectionType::ConstPointer counted = AddQuantumNoise(options, filter->GetOutput(), options.seed);
  WriteOutputs(options,
               counted,
               pointBased && !options.standardErrorOutput.empty() ? pointBased->GetStandardErrorOutput() : nullptr,
               notes);
  const std::string geometryPath = WriteGeometryBeside(options.output, geometry);
  stages.emplace_back("write", SecondsSince(start));

  if (options.verbose)
  {
    if (pointBased)
    {
      std::cerr << "pbdrr: sampler " << options.sampler << ", samples " << options.samples << ", seed " << options.seed
                << ", kernel " << itk::DRRPolicies::Kernels::GetName(options.kernel) << ", splat "
                << itk::DRRPolicies::Splats::GetName(options.splat) << ", attenuation mass M "
                << pointBased->GetTotalMass() << " mm^2, points on the detector " << pointBased->GetPointsOnDetector()
                << std::endl;
      if (const itk::DRRControlVariate * split = pointBased->GetControlVariate())
      {
        std::cerr << "pbdrr: control variate F " << split->GetFactor() << ": residual mass M_r "
                  << split->GetResidualMass() << " mm^2, M_r / M " << split->GetResidualMass() / split->GetTotalMass()
                  << ", coarse image 2 x " << options.raysPerSide << " x " << options.raysPerSide
                  << " antithetic ray pairs per pixel" << std::endl;
      }
      const std::string statistics = pointBased->GetSampler()->GetStatisticsSummary();
      if (!statistics.empty())
      {
        std::cerr << "pbdrr: " << options.sampler << ": " << statistics << std::endl;
      }
    }
    for (const auto & note : notes)
    {
      std::cerr << "pbdrr: " << note << std::endl;
    }
    std::cerr << "pbdrr: time:";
    for (const auto & stage : stages)
    {
      std::cerr << " " << stage.first << " " << std::fixed << std::setprecision(3) << stage.second << " s;";
    }
    std::cerr << std::endl;
  }
  if (chatty)
  {
    std::cerr << "pbdrr: wrote " << options.output
              << (options.standardErrorOutput.empty() ? "" : " and " + options.standardErrorOutput) << ", its view in "
              << geometryPath << std::endl;
  }
}
} // namespace pbdrr
