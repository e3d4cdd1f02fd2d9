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
#include "pbdrrImageOutputs.h"
#include "pbdrrMessages.h"
#include "pbdrrOutputFiles.h"

#include "itkDRROutputConversion.h"
#include "itkDRRProjectionGeometryFileIO.h"
#include "itkDRRProjectionMatrixFileIO.h"
#include "itkImageFileWriter.h"

#include <algorithm>
#include <cstdio>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <sys/stat.h>
#include <unistd.h>

namespace pbdrr
{
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
using GrayType = itk::Image<unsigned char, 2>;
using Gray16Type = itk::Image<unsigned short, 2>;
using OutputModeEnum = itk::PointBasedDRREnums::OutputMode;

/** Writes an image at path through a temporary name (WriteAtomically), or directly for a format of two files. */
template <typename TImage>
void
WriteImageAtomically(const TImage * image, const std::string & path)
{
  if (HasDetachedHeader(path))
  {
    itk::WriteImage(image, path);
    try
    {
      CheckWrittenImage(path, path);
    }
    catch (...)
    {
      std::remove(path.c_str()); // the header: no reader takes the cut data file for an image
      throw;
    }
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
  double low = 0.0;
  itk::DRROutputConversion::ComputeAutomaticWindow(
    image->GetBufferPointer(), image->GetBufferPointer() + image->GetBufferedRegion().GetNumberOfPixels(), low, width);
  level = low + 0.5 * width;
}

/** The gray image of a window [low, low + width] of the line integrals, by the library's conversion
 * (DRROutputConversion, as the filters' Gray8 and Gray16 make it): the window onto 0 .. the pixel type's largest
 * level, rounded to the nearest level, attenuating bright. */
template <typename TGray>
void
WriteGray(const ProjectionType * lineIntegral, double low, double width, const std::string & path)
{
  using GrayPixelType = typename TGray::PixelType;
  const itk::DRROutputConversion conversion(
    sizeof(GrayPixelType) == 1 ? OutputModeEnum::Gray8 : OutputModeEnum::Gray16, low, width);
  auto gray = TGray::New();
  gray->CopyInformation(lineIntegral);
  gray->SetRegions(lineIntegral->GetLargestPossibleRegion());
  gray->Allocate();
  const float *   in = lineIntegral->GetBufferPointer();
  GrayPixelType * out = gray->GetBufferPointer();
  for (size_t p = 0; p < gray->GetBufferedRegion().GetNumberOfPixels(); ++p)
  {
    out[p] = static_cast<GrayPixelType>(conversion.Value(in[p]));
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
    text << "# a " << itk::PointBasedDRREnums::GetName(geometry->GetProjection())
         << " beam has no 3 x 4 projection matrix: the view is the keys below\n";
  }
  itk::DRRProjectionGeometryFileIO::WriteToStream(text, geometry);
  WriteAtomically(path, [&](const std::string & temporary) {
    std::ofstream file(temporary);
    file << text.str();
    file.close();
    if (!file)
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
      WriteGray<GrayType>(lineIntegral, level - 0.5 * width, width, options.output);
    }
    else
    {
      WriteGray<Gray16Type>(lineIntegral, level - 0.5 * width, width, options.output);
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
} // namespace pbdrr
