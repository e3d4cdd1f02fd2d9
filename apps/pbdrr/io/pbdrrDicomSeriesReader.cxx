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
#include "pbdrrDicomSeriesReader.h"
#include "pbdrrDicomContent.h"
#include "pbdrrDicomSliceReader.h"
#include "pbdrrDicomSliceStack.h"
#include "pbdrrDicomValues.h"
#include "pbdrrGdcmWarningCapture.h"
#include "pbdrrLoaderText.h"

#include "itkCommand.h"
#include "itkGDCMImageIO.h"
#include "itkImageSeriesReader.h"
#include "gdcmScanner.h"

#include <cmath>
#include <stdexcept>

namespace pbdrr
{
namespace
{
/** What one scan of a series' headers gives: its slices, and whether its values fit an int16. */
struct ScannedSeries
{
  std::vector<Slice> Slices;     // one per file
  bool               HoldsInt16; // see FileHoldsInt16()
};

/** True if a file's pixel values, as GDCM gives them (stored value x slope + intercept), are integers an int16 holds,
 * read from its header alone: Bits Stored, Pixel Representation, Samples per Pixel, Rescale Slope and Intercept. */
bool
FileHoldsInt16(const gdcm::Scanner & scanner, const std::string & file)
{
  const auto number = [&](uint16_t element, double fallback, bool & present) {
    std::vector<double> value;
    present = ParseNumbers(scanner.GetValue(file.c_str(), gdcm::Tag(0x0028, element)), 1, value);
    return present ? value[0] : fallback;
  };
  bool         present = false;
  const double bitsStored = number(0x0101, 0.0, present);
  if (!present || bitsStored < 1.0 || bitsStored > 16.0)
  {
    return false;
  }
  const double representation = number(0x0103, 0.0, present);
  const double samples = number(0x0002, 1.0, present);
  const double slope = number(0x1053, 1.0, present);
  const double intercept = number(0x1052, 0.0, present);
  if (samples != 1.0 || slope != 1.0 || intercept != std::floor(intercept))
  {
    return false;
  }
  const double levels = std::ldexp(1.0, static_cast<int>(bitsStored));
  const double lowest = (representation == 1.0 ? -levels / 2.0 : 0.0) + intercept;
  const double highest = (representation == 1.0 ? levels / 2.0 - 1.0 : levels - 1.0) + intercept;
  return lowest >= -32768.0 && highest <= 32767.0;
}

/** The slices of a series, one per file, and whether every file's values fit an int16, from one scan of their DICOM
 * headers. */
ScannedSeries
ScanSeries(const std::vector<std::string> & files)
{
  const gdcm::Tag positionTag(0x0020, 0x0032);
  const gdcm::Tag orientationTag(0x0020, 0x0037);
  const gdcm::Tag rowsTag(0x0028, 0x0010);
  const gdcm::Tag columnsTag(0x0028, 0x0011);
  gdcm::Scanner   scanner;
  for (const gdcm::Tag & tag : { positionTag, orientationTag, rowsTag, columnsTag })
  {
    scanner.AddTag(tag);
  }
  for (const uint16_t element : { 0x0101, 0x0103, 0x0002, 0x1053, 0x1052 }) // FileHoldsInt16()'s
  {
    scanner.AddTag(gdcm::Tag(0x0028, element));
  }
  if (!scanner.Scan(files))
  {
    Fail("cannot scan the DICOM files of the series");
  }
  ScannedSeries series{ {}, true };
  for (const std::string & file : files)
  {
    Slice               slice;
    std::vector<double> position;
    if (!ParseNumbers(scanner.GetValue(file.c_str(), orientationTag), 6, slice.Orientation) ||
        !ParseNumbers(scanner.GetValue(file.c_str(), positionTag), 3, position))
    {
      Fail("DICOM file " + file + " has no image position/orientation (not a CT slice?)");
    }
    const char * rows = scanner.GetValue(file.c_str(), rowsTag);
    const char * columns = scanner.GetValue(file.c_str(), columnsTag);
    slice.Name = file;
    slice.Position = { position[0], position[1], position[2] };
    slice.Size = std::string(rows ? rows : "") + " x " + (columns ? columns : "");
    series.Slices.push_back(slice);
    series.HoldsInt16 = series.HoldsInt16 && FileHoldsInt16(scanner, file);
  }
  return series;
}

/** The slices read one file after the other by itk::ImageSeriesReader: for the files ReadDicomSlices leaves to it. */
template <typename TVolume>
typename TVolume::Pointer
ReadSlicesOneByOne(const std::vector<std::string> & files, bool forceOrthogonalDirection, const LoadProgress & progress)
{
  auto reader = itk::ImageSeriesReader<TVolume>::New();
  reader->SetImageIO(itk::GDCMImageIO::New());
  reader->SetFileNames(files);
  reader->SetForceOrthogonalDirection(forceOrthogonalDirection);
  if (progress)
  {
    // ImageSeriesReader reports its progress once per file read.
    auto observer = itk::CStyleCommand::New();
    struct Context
    {
      const LoadProgress * Progress;
      size_t               Files;
    } context{ &progress, files.size() };
    observer->SetClientData(&context);
    observer->SetCallback([](itk::Object * caller, const itk::EventObject &, void * data) {
      const auto * c = static_cast<const Context *>(data);
      const float  fraction = static_cast<itk::ProcessObject *>(caller)->GetProgress();
      (*c->Progress)(static_cast<size_t>(fraction * static_cast<float>(c->Files) + 0.5f), c->Files);
    });
    reader->AddObserver(itk::ProgressEvent(), observer);
  }
  reader->Update();
  typename TVolume::Pointer image = reader->GetOutput();
  image->DisconnectPipeline();
  return image;
}

template <typename TVolume>
typename TVolume::Pointer
ReadSlices(const std::vector<std::string> & files, const SliceStack & stack, const LoadProgress & progress)
{
  // A gantry tilt is a sheared grid. By default ITK's series reader forces the third direction onto the slice normal,
  // which places every slice but the first wrongly; without that, it takes the step from the first slice to the last:
  // a non-orthogonal direction matrix, which the DRR filters map exactly (any invertible affine).
  const Vector3 & shear = stack.ShearPerMillimetre;
  const bool      forceOrthogonalDirection = shear[0] == 0.0 && shear[1] == 0.0 && shear[2] == 0.0;
  // The files decoded in parallel, straight into the volume (the same volume as ImageSeriesReader's); the rare series
  // it does not decode (compressed but for JPEG 2000, colour, multi-frame, ...) are read by ImageSeriesReader.
  typename TVolume::Pointer image = ReadDicomSlices<TVolume>(files, forceOrthogonalDirection, progress);
  if (!image)
  {
    image = ReadSlicesOneByOne<TVolume>(files, forceOrthogonalDirection, progress);
  }
  auto imageSpacing = image->GetSpacing();
  imageSpacing[2] = stack.StepLength(); // mm from slice to slice along the third axis: the slices' own, not GDCM's
  image->SetSpacing(imageSpacing);
  return image;
}
} // namespace

void
ReadDicomSeries(const std::vector<std::string> & files,
                const std::vector<std::string> & notDicom,
                const std::string &              directory,
                LoadedVolume &                   loaded,
                const LoadProgress &             progress)
{
  GdcmWarningCapture warnings;
  SliceStack         stack;
  bool               holdsInt16 = false;
  try
  {
    const ScannedSeries series = ScanSeries(files);
    holdsInt16 = series.HoldsInt16;
    stack = CheckSliceStack(series.Slices, "the series", true);
  }
  catch (const std::runtime_error & e)
  {
    // A slice cut to a few bytes no longer looks like DICOM: name such files beside the gap they leave.
    Fail(e.what() + (notDicom.empty() ? std::string()
                                      : " (" + directory + " also holds " + std::to_string(notDicom.size()) +
                                          " file(s) that are not DICOM: " + JoinNames(notDicom) + ")"));
  }
  // CT as stored (2 bytes per voxel) when every slice's values fit an int16, as they do on nearly every scanner.
  if (holdsInt16)
  {
    loaded.Set(ReadSlices<HUVolumeType>(files, stack, progress));
  }
  else
  {
    loaded.Set(ReadSlices<VolumeType>(files, stack, progress));
  }
  RefuseDamagedPixelData(warnings, files);
}
} // namespace pbdrr
