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
#include "pbdrrDicomMultiFrame.h"
#include "pbdrrDicomContent.h"
#include "pbdrrDicomSliceStack.h"
#include "pbdrrDicomValues.h"
#include "pbdrrGdcmWarningCapture.h"
#include "pbdrrLoaderText.h"
#include "pbdrrVolumeFileReader.h"

#include "itkGDCMImageIO.h"
#include "gdcmReader.h"

#include <cmath>
#include <sstream>

namespace pbdrr
{
namespace
{
/** The frames of an (enhanced) multi-frame file with their positions from the per-frame functional groups; empty if
 * the file gives no per-frame positions (a legacy multi-frame object). */
std::vector<Slice>
ReadFramePositions(const std::string & file, const gdcm::DataSet & dataSet)
{
  const gdcm::Tag sharedTag(0x5200, 0x9229);
  const gdcm::Tag perFrameTag(0x5200, 0x9230);
  const gdcm::Tag planePositionTag(0x0020, 0x9113);
  const gdcm::Tag planeOrientationTag(0x0020, 0x9116);
  const gdcm::Tag positionTag(0x0020, 0x0032);
  const gdcm::Tag orientationTag(0x0020, 0x0037);

  std::vector<gdcm::SmartPointer<gdcm::SequenceOfItems>> keep;
  const auto                                             shared = SequenceItems(dataSet, sharedTag, keep);
  const auto                                             perFrame = SequenceItems(dataSet, perFrameTag, keep);
  std::string                                            sharedOrientation;
  if (!shared.empty())
  {
    FunctionalGroupValue(*shared.front(), planeOrientationTag, orientationTag, sharedOrientation);
  }
  std::string rows, columns;
  StringValue(dataSet, gdcm::Tag(0x0028, 0x0010), rows);
  StringValue(dataSet, gdcm::Tag(0x0028, 0x0011), columns);

  std::vector<Slice> frames;
  for (size_t k = 0; k < perFrame.size(); ++k)
  {
    std::string position, orientation = sharedOrientation;
    if (!FunctionalGroupValue(*perFrame[k], planePositionTag, positionTag, position))
    {
      return {};
    }
    FunctionalGroupValue(*perFrame[k], planeOrientationTag, orientationTag, orientation);
    Slice               frame;
    std::vector<double> numbers;
    if (!ParseNumbers(position.c_str(), 3, numbers) || !ParseNumbers(orientation.c_str(), 6, frame.Orientation))
    {
      Fail("frame " + std::to_string(k + 1) + " of the multi-frame DICOM file " + file +
           " has no valid image position/orientation");
    }
    frame.Name = file + ", frame " + std::to_string(k + 1);
    frame.Position = { numbers[0], numbers[1], numbers[2] };
    frame.Size = rows + " x " + columns;
    frames.push_back(frame);
  }
  return frames;
}

/** Where a legacy multi-frame object says its frames lie: Spacing Between Slices (0018,0088), positive, and Pixel
 * Spacing (0028,0030). False if it does not say. */
bool
ReadLegacySpacing(const gdcm::DataSet & dataSet,
                  std::vector<double> & spacingBetweenSlices,
                  std::vector<double> & pixelSpacing)
{
  std::string text;
  return StringValue(dataSet, gdcm::Tag(0x0018, 0x0088), text) && ParseNumbers(text.c_str(), 1, spacingBetweenSlices) &&
         spacingBetweenSlices[0] > 0.0 && StringValue(dataSet, gdcm::Tag(0x0028, 0x0030), text) &&
         ParseNumbers(text.c_str(), 2, pixelSpacing);
}

/** Places a legacy object's frames by its Spacing Between Slices: GDCM places them 1 mm apart whatever it says. Pixel
 * Spacing is the spacing between rows (along y), then between columns (along x): GDCM must agree with it. */
void
PlaceLegacyFrames(VolumeType *                image,
                  const std::string &         fileName,
                  const std::vector<double> & pixelSpacing,
                  double                      spacingBetweenSlices,
                  std::vector<std::string> &  notes)
{
  auto spacing = image->GetSpacing();
  for (unsigned int a = 0; a < 2; ++a)
  {
    const double expected = pixelSpacing[1 - a];
    if (std::abs(spacing[a] - expected) > 1e-4 * expected)
    {
      std::ostringstream message;
      message << "GDCM reads the multi-frame DICOM file " << fileName << " with a pixel spacing of " << spacing[0]
              << " x " << spacing[1] << " mm, but its Pixel Spacing (0028,0030) says " << pixelSpacing[1] << " x "
              << pixelSpacing[0] << " mm; pbdrr does not render it rather than render it wrong";
      Fail(message.str());
    }
  }
  spacing[2] = spacingBetweenSlices;
  image->SetSpacing(spacing);
  notes.push_back(fileName + " gives no per-frame positions: its frames are placed " +
                  Millimetres(spacingBetweenSlices) + " apart, by its Spacing Between Slices (0018,0088)");
}

/** Places the frames where their per-frame positions put them, whatever GDCM made of them: the first frame stored at
 * the origin, the third axis towards the next. */
void
PlaceFramesByPositions(VolumeType * image, const std::vector<Slice> & frames, const SliceStack & stack)
{
  const Vector3 &           first = frames.front().Position;
  const double              sign = stack.Increasing ? 1.0 : -1.0;
  VolumeType::PointType     origin;
  VolumeType::DirectionType direction;
  for (unsigned int r = 0; r < 3; ++r)
  {
    origin[r] = first[r];
    direction[r][0] = frames[0].Orientation[r];
    direction[r][1] = frames[0].Orientation[3 + r];
    direction[r][2] = sign * stack.Normal[r];
  }
  auto spacing = image->GetSpacing();
  spacing[2] = stack.Spacing;
  image->SetOrigin(origin);
  image->SetSpacing(spacing);
  image->SetDirection(direction);
}

/** Reads a multi-frame DICOM file as a volume (ReadDicomFile without its check of the pixel data). */
VolumeType::Pointer
ReadMultiFrameFile(const std::string & file, std::vector<std::string> & notes)
{
  gdcm::Reader header;
  header.SetFileName(file.c_str());
  if (!header.ReadUpToTag(gdcm::Tag(0x7fe0, 0x0010)))
  {
    Fail("cannot read the DICOM file " + file + ": truncated or damaged");
  }
  const gdcm::DataSet & dataSet = header.GetFile().GetDataSet();
  std::string           text;
  std::vector<double>   numberOfFrames;
  if (!StringValue(dataSet, gdcm::Tag(0x0028, 0x0008), text) || !ParseNumbers(text.c_str(), 1, numberOfFrames) ||
      !(numberOfFrames[0] > 1.0))
  {
    Fail("the DICOM file " + file + " is a single 2D slice; pbdrr needs a volume");
  }
  const std::vector<Slice> frames = ReadFramePositions(file, dataSet);
  SliceStack               stack;
  std::vector<double>      spacingBetweenSlices, pixelSpacing;
  if (!frames.empty())
  {
    if (static_cast<double>(frames.size()) != numberOfFrames[0])
    {
      Fail("the multi-frame DICOM file " + file + " has " + text + " frames but " + std::to_string(frames.size()) +
           " per-frame positions");
    }
    stack = CheckSliceStack(frames, "the frames of " + file);
    if (!stack.Ordered)
    {
      Fail("the frames of " + file +
           " are not stored in slice order (their positions go back and forth along the normal); pbdrr does not "
           "reorder them");
    }
  }
  else if (!ReadLegacySpacing(dataSet, spacingBetweenSlices, pixelSpacing))
  {
    Fail("the multi-frame DICOM file " + file +
         " gives neither per-frame positions nor a Spacing Between Slices (0018,0088) and Pixel Spacing (0028,0030): "
         "where its frames lie is unknown; pbdrr does not render it rather than render it wrong");
  }

  auto io = itk::GDCMImageIO::New();
  io->SetFileName(file);
  io->ReadImageInformation();
  VolumeType::Pointer image = ReadVolumeFile(file, io.GetPointer());
  if (frames.empty())
  {
    PlaceLegacyFrames(image, file, pixelSpacing, spacingBetweenSlices[0], notes);
  }
  else
  {
    PlaceFramesByPositions(image, frames, stack);
  }
  return image;
}
} // namespace

VolumeType::Pointer
ReadDicomFile(const std::string & file, std::vector<std::string> & notes)
{
  GdcmWarningCapture  warnings;
  VolumeType::Pointer image = ReadMultiFrameFile(file, notes);
  RefuseDamagedPixelData(warnings, { file });
  return image;
}
} // namespace pbdrr
