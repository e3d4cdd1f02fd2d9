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
#include "pbdrrVolumeLoader.h"
#include "pbdrrDicomFileCheck.h"

#include "itkGDCMImageIO.h"
#include "itkGDCMSeriesFileNames.h"
#include "itkImageFileReader.h"
#include "itkImageIOFactory.h"
#include "itkImageSeriesReader.h"
#include "gdcmReader.h"
#include "gdcmScanner.h"
#include "gdcmSequenceOfItems.h"
#include "gdcmTrace.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <set>
#include <sstream>
#include <stdexcept>
#include <sys/stat.h>

namespace pbdrr
{
namespace
{
using Vector3 = std::array<double, 3>;

[[noreturn]] void
Fail(const std::string & message)
{
  throw std::runtime_error(message);
}

bool
ParseNumbers(const char * text, size_t count, std::vector<double> & numbers)
{
  numbers.clear();
  if (text == nullptr)
  {
    return false;
  }
  std::string s(text);
  std::replace(s.begin(), s.end(), '\\', ' ');
  std::istringstream stream(s);
  for (double v; stream >> v;)
  {
    numbers.push_back(v);
  }
  return numbers.size() == count;
}

Vector3
Cross(const Vector3 & a, const Vector3 & b)
{
  return { a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0] };
}

double
Dot(const Vector3 & a, const Vector3 & b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

std::string
Millimetres(double value)
{
  std::ostringstream s;
  s.precision(4);
  s << value << " mm";
  return s.str();
}

/** One slice of a DICOM volume: a file of a series, or a frame of a multi-frame file. */
struct Slice
{
  std::string         Name;        // the file, or the file and frame
  Vector3             Position;    // Image Position (Patient), mm
  std::vector<double> Orientation; // Image Orientation (Patient): row and column direction cosines
  std::string         Size;        // rows x columns
};

/** How the slices stack up along their normal. */
struct SliceStack
{
  Vector3 Normal{ { 0.0, 0.0, 1.0 } }; // row direction x column direction of the slices
  double  Spacing{ 1.0 };              // mm between neighbouring slices
  bool    Increasing{ true };          // given in increasing position along the normal
  bool    Ordered{ true };             // given in increasing or decreasing order, not shuffled
};

/** Checks that the slices form one regular 3D grid: one orientation and size, positions along the normal (no gantry
 * tilt), no duplicates, no gaps, even spacing. `what` names them in messages ("the series", "the frames of F"). */
SliceStack
CheckSliceStack(const std::vector<Slice> & slices, const std::string & what)
{
  SliceStack stack;
  if (slices.size() < 2)
  {
    return stack;
  }
  const Slice & first = slices.front();
  for (const Slice & slice : slices)
  {
    for (size_t i = 0; i < 6; ++i)
    {
      if (std::abs(slice.Orientation[i] - first.Orientation[i]) > 1e-4)
      {
        Fail("the slices of " + what + " have different orientations (" + slice.Name + "): not one volume");
      }
    }
    if (slice.Size != first.Size)
    {
      Fail("the slices of " + what + " have different sizes (" + slice.Name + "): not one volume");
    }
  }
  const Vector3 rowDirection{ first.Orientation[0], first.Orientation[1], first.Orientation[2] };
  const Vector3 columnDirection{ first.Orientation[3], first.Orientation[4], first.Orientation[5] };
  const Vector3 normal = Cross(rowDirection, columnDirection);
  stack.Normal = normal;
  std::vector<double> depth(slices.size());
  for (size_t i = 0; i < slices.size(); ++i)
  {
    depth[i] = Dot(slices[i].Position, normal);
  }
  std::vector<size_t> order(slices.size());
  for (size_t i = 0; i < order.size(); ++i)
  {
    order[i] = i;
  }
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return depth[a] < depth[b]; });
  std::vector<double> gaps;
  for (size_t i = 1; i < order.size(); ++i)
  {
    const Vector3 & a = slices[order[i - 1]].Position;
    const Vector3 & b = slices[order[i]].Position;
    const Vector3   step{ b[0] - a[0], b[1] - a[1], b[2] - a[2] };
    const double    along = Dot(step, normal);
    const double    across = std::sqrt(std::max(0.0, Dot(step, step) - along * along));
    if (along < 1e-3)
    {
      Fail("two slices of " + what + " lie at the same position (" + Millimetres(depth[order[i]]) +
           " along the slice normal): duplicated or mixed series");
    }
    if (across > 1e-3 * along + 0.01)
    {
      Fail("the slice positions of " + what +
           " are not along the slice normal (gantry tilt or sheared series: each slice is shifted " +
           Millimetres(across) + " sideways per " + Millimetres(along) +
           " step); pbdrr does not render tilted series: resample to an orthogonal grid first");
    }
    gaps.push_back(along);
  }
  std::vector<double> sorted = gaps;
  std::sort(sorted.begin(), sorted.end());
  stack.Spacing = sorted[sorted.size() / 2];
  for (size_t i = 0; i < gaps.size(); ++i)
  {
    if (std::abs(gaps[i] - stack.Spacing) > 0.01 * stack.Spacing + 1e-3)
    {
      const double       ratio = gaps[i] / stack.Spacing;
      const bool         missing = ratio > 1.5 && std::abs(ratio - std::round(ratio)) < 0.05;
      std::ostringstream message;
      message << (missing ? "missing slice(s)" : "uneven slice spacing") << " in " << what << ": slices " << i
              << " and " << i + 1 << " (at " << Millimetres(depth[order[i]]) << " and "
              << Millimetres(depth[order[i + 1]]) << " along the normal) are " << Millimetres(gaps[i])
              << " apart, the spacing is " << Millimetres(stack.Spacing);
      if (missing)
      {
        message << " (" << std::lround(ratio) - 1 << " slice(s) missing)";
      }
      message << "; pbdrr does not render it rather than render it wrong";
      Fail(message.str());
    }
  }
  bool increasing = true;
  bool decreasing = true;
  for (size_t i = 0; i < order.size(); ++i)
  {
    increasing = increasing && order[i] == i;
    decreasing = decreasing && order[i] == order.size() - 1 - i;
  }
  stack.Increasing = increasing;
  stack.Ordered = increasing || decreasing;
  return stack;
}

/** The slices of a series, one per file, from their DICOM headers. */
std::vector<Slice>
ScanSeries(const std::vector<std::string> & files)
{
  const gdcm::Tag positionTag(0x0020, 0x0032);
  const gdcm::Tag orientationTag(0x0020, 0x0037);
  const gdcm::Tag rowsTag(0x0028, 0x0010);
  const gdcm::Tag columnsTag(0x0028, 0x0011);
  gdcm::Scanner   scanner;
  scanner.AddTag(positionTag);
  scanner.AddTag(orientationTag);
  scanner.AddTag(rowsTag);
  scanner.AddTag(columnsTag);
  if (!scanner.Scan(files))
  {
    Fail("cannot scan the DICOM files of the series");
  }
  std::vector<Slice> slices;
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
    slices.push_back(slice);
  }
  return slices;
}

/** The items of sequence `tag` in a data set (empty if absent). */
std::vector<const gdcm::DataSet *>
SequenceItems(const gdcm::DataSet &                                    dataSet,
              const gdcm::Tag &                                        tag,
              std::vector<gdcm::SmartPointer<gdcm::SequenceOfItems>> & keep)
{
  std::vector<const gdcm::DataSet *> items;
  if (!dataSet.FindDataElement(tag))
  {
    return items;
  }
  gdcm::SmartPointer<gdcm::SequenceOfItems> sequence = dataSet.GetDataElement(tag).GetValueAsSQ();
  if (!sequence)
  {
    return items;
  }
  keep.push_back(sequence);
  for (gdcm::SequenceOfItems::SizeType i = 1; i <= sequence->GetNumberOfItems(); ++i)
  {
    items.push_back(&sequence->GetItem(i).GetNestedDataSet());
  }
  return items;
}

/** The string value of `tag` in a data set, or nullptr-like empty if absent. */
bool
StringValue(const gdcm::DataSet & dataSet, const gdcm::Tag & tag, std::string & value)
{
  if (!dataSet.FindDataElement(tag))
  {
    return false;
  }
  const gdcm::ByteValue * bytes = dataSet.GetDataElement(tag).GetByteValue();
  if (!bytes)
  {
    return false;
  }
  value.assign(bytes->GetPointer(), bytes->GetLength());
  return true;
}

/** Value `tag` of the functional group `groupTag` (e.g. Plane Position Sequence) of one functional-groups item. */
bool
FunctionalGroupValue(const gdcm::DataSet & groups,
                     const gdcm::Tag &     groupTag,
                     const gdcm::Tag &     tag,
                     std::string &         value)
{
  std::vector<gdcm::SmartPointer<gdcm::SequenceOfItems>> keep;
  const auto                                             items = SequenceItems(groups, groupTag, keep);
  return !items.empty() && StringValue(*items.front(), tag, value);
}

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

/** Listens to GDCM while it reads: it reports pixel data cut short (and then fills the gap) only as a warning; its
 * errors are kept out of the user's way too (pbdrr says what went wrong in its own words). */
class GdcmWarningCapture
{
public:
  GdcmWarningCapture()
    : m_WarningsWereOn(gdcm::Trace::GetWarningFlag())
    , m_WarningStream(gdcm::Trace::GetWarningStream())
    , m_ErrorStream(gdcm::Trace::GetErrorStream())
  {
    gdcm::Trace::SetWarningStream(m_Text);
    gdcm::Trace::SetErrorStream(m_Text);
    gdcm::Trace::WarningOn();
  }
  ~GdcmWarningCapture()
  {
    gdcm::Trace::SetWarning(m_WarningsWereOn);
    gdcm::Trace::SetWarningStream(m_WarningStream);
    gdcm::Trace::SetErrorStream(m_ErrorStream);
  }
  GdcmWarningCapture(const GdcmWarningCapture &) = delete;
  GdcmWarningCapture &
  operator=(const GdcmWarningCapture &) = delete;

  /** GDCM found the pixel data incomplete (a truncated file) or a compressed fragment unreadable. */
  bool
  PixelDataDamaged() const
  {
    const std::string text = m_Text.str();
    return text.find("Incomplete Pixel Data") != std::string::npos ||
           text.find("Fragment could not be read") != std::string::npos ||
           text.find("could be corrupted") != std::string::npos;
  }

private:
  std::ostringstream m_Text;
  bool               m_WarningsWereOn;
  std::ostream &     m_WarningStream;
  std::ostream &     m_ErrorStream;
};

/** What a DICOM file holds, for the files of a directory that no series took. */
enum class DicomContent
{
  NotDicom,
  Damaged, // starts as DICOM, but GDCM cannot parse it, or its pixel data is cut short
  NoImage, // a DICOM object without pixel data: a report, a structure set, ...
  Image
};

DicomContent
ClassifyFile(const std::string & file)
{
  if (!IsDicomPart10File(file))
  {
    return DicomContent::NotDicom;
  }
  GdcmWarningCapture warnings;
  gdcm::Reader       reader;
  reader.SetFileName(file.c_str());
  if (!reader.Read() || warnings.PixelDataDamaged())
  {
    return DicomContent::Damaged;
  }
  const gdcm::DataSet & dataSet = reader.GetFile().GetDataSet();
  if (dataSet.FindDataElement(gdcm::Tag(0x7fe0, 0x0010)))
  {
    return DicomContent::Image;
  }
  // No pixel data. Every DICOM object names its SOP class; a CT image without pixels is a file cut short at an
  // element boundary (its header walks clean), not a report.
  std::string sopClass, modality;
  if (!StringValue(dataSet, gdcm::Tag(0x0008, 0x0016), sopClass))
  {
    return DicomContent::Damaged;
  }
  StringValue(dataSet, gdcm::Tag(0x0008, 0x0060), modality);
  const bool ctImage = sopClass.rfind("1.2.840.10008.5.1.4.1.1.2", 0) == 0 || modality.rfind("CT", 0) == 0 ||
                       dataSet.FindDataElement(gdcm::Tag(0x0028, 0x0010));
  return ctImage ? DicomContent::Damaged : DicomContent::NoImage;
}

std::string
JoinNames(const std::vector<std::string> & files)
{
  std::string list;
  for (size_t i = 0; i < files.size() && i < 5; ++i)
  {
    list += (i ? ", " : "") + files[i].substr(files[i].find_last_of('/') + 1);
  }
  return files.size() > 5 ? list + ", ..." : list;
}

VolumeType::Pointer
ReadFile(const std::string & path, const itk::ImageIOBase::Pointer & io)
{
  if (io->GetNumberOfDimensions() != 3)
  {
    Fail(path + " is a " + std::to_string(io->GetNumberOfDimensions()) +
         "D image; pbdrr needs a 3D volume (a CT series or volume file)");
  }
  if (io->GetNumberOfComponents() != 1)
  {
    Fail(path + " has " + std::to_string(io->GetNumberOfComponents()) +
         " components per voxel; pbdrr needs scalar voxels (HU or mu)");
  }
  auto reader = itk::ImageFileReader<VolumeType>::New();
  reader->SetFileName(path);
  reader->SetImageIO(io);
  // Some readers (MetaImage) report a short read on std::cerr and carry on: listen, and refuse such a volume.
  std::ostringstream readerMessages;
  std::streambuf *   standardError = std::cerr.rdbuf(readerMessages.rdbuf());
  try
  {
    reader->Update();
  }
  catch (...)
  {
    std::cerr.rdbuf(standardError);
    throw;
  }
  std::cerr.rdbuf(standardError);
  const std::string messages = readerMessages.str();
  if (messages.find("not read completely") != std::string::npos || messages.find("rror") != std::string::npos)
  {
    Fail("cannot read " + path + ": the file is truncated or damaged (" + messages.substr(0, messages.find('\n')) +
         ")");
  }
  std::cerr << messages;
  VolumeType::Pointer image = reader->GetOutput();
  image->DisconnectPipeline(); // the volume is data from now on: no reader re-executes behind it
  return image;
}

/** The regular files of a directory, sorted by name (so that messages name them in a stable order). */
std::vector<std::string>
SortedRegularFiles(const std::string & directory)
{
  std::vector<std::string> files;
  for (const auto & entry : std::filesystem::directory_iterator(directory))
  {
    if (entry.is_regular_file())
    {
      files.push_back(entry.path().string());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

/** Refuses a directory that holds a DICOM file cut short, before GDCM reads it (GDCM may abort on such a file). */
void
RefuseTruncatedFiles(const std::vector<std::string> & files, const std::string & directory)
{
  std::vector<std::string> truncated;
  std::string              first;
  for (const auto & file : files)
  {
    const std::string problem = FindDicomTruncation(file);
    if (!problem.empty())
    {
      truncated.push_back(file);
      first = first.empty() ? problem : first;
    }
  }
  if (!truncated.empty())
  {
    Fail(std::to_string(truncated.size()) + " DICOM file(s) in " + directory +
         " are truncated or damaged: " + JoinNames(truncated) + " (" + first +
         "); pbdrr does not render a series with a slice cut short or left out: repair or remove them");
  }
}

/** Reads a multi-frame DICOM file as a volume. An enhanced file's frames are placed where their per-frame positions
 * say (checked as a series' slices are; frames stored downwards give a third axis pointing down); a legacy file
 * without them is placed by its Spacing Between Slices, if GDCM agrees with its Pixel Spacing. */
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
  else if (!StringValue(dataSet, gdcm::Tag(0x0018, 0x0088), text) ||
           !ParseNumbers(text.c_str(), 1, spacingBetweenSlices) || !(spacingBetweenSlices[0] > 0.0) ||
           !StringValue(dataSet, gdcm::Tag(0x0028, 0x0030), text) || !ParseNumbers(text.c_str(), 2, pixelSpacing))
  {
    Fail("the multi-frame DICOM file " + file +
         " gives neither per-frame positions nor a Spacing Between Slices (0018,0088) and Pixel Spacing (0028,0030): "
         "where its frames lie is unknown; pbdrr does not render it rather than render it wrong");
  }

  auto io = itk::GDCMImageIO::New();
  io->SetFileName(file);
  io->ReadImageInformation();
  VolumeType::Pointer image = ReadFile(file, io.GetPointer());
  if (frames.empty())
  {
    // GDCM places a legacy object's frames 1 mm apart whatever it says: its Spacing Between Slices decides. Pixel
    // Spacing is the spacing between rows (along y), then between columns (along x): GDCM must agree with it.
    auto spacing = image->GetSpacing();
    for (unsigned int a = 0; a < 2; ++a)
    {
      const double expected = pixelSpacing[1 - a];
      if (std::abs(spacing[a] - expected) > 1e-4 * expected)
      {
        std::ostringstream message;
        message << "GDCM reads the multi-frame DICOM file " << file << " with a pixel spacing of " << spacing[0]
                << " x " << spacing[1] << " mm, but its Pixel Spacing (0028,0030) says " << pixelSpacing[1] << " x "
                << pixelSpacing[0] << " mm; pbdrr does not render it rather than render it wrong";
        Fail(message.str());
      }
    }
    spacing[2] = spacingBetweenSlices[0];
    image->SetSpacing(spacing);
    notes.push_back(file + " gives no per-frame positions: its frames are placed " +
                    Millimetres(spacingBetweenSlices[0]) + " apart, by its Spacing Between Slices (0018,0088)");
    return image;
  }
  // Where the per-frame positions put the frames, whatever GDCM made of them: the first frame stored at the origin,
  // the third axis towards the next.
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
  return image;
}

/** Refuses what GDCM read with complaints about the pixel data (it fills what is missing and carries on). */
void
RefuseDamagedPixelData(const GdcmWarningCapture & warnings, const std::vector<std::string> & files)
{
  if (!warnings.PixelDataDamaged())
  {
    return;
  }
  std::vector<std::string> damaged;
  for (const auto & file : files)
  {
    if (ClassifyFile(file) == DicomContent::Damaged)
    {
      damaged.push_back(file);
    }
  }
  Fail("the pixel data of " + (damaged.empty() ? std::string("the DICOM files") : JoinNames(damaged)) +
       " is incomplete or damaged; pbdrr does not render it rather than render it wrong");
}

/** A DICOM file read alone: a multi-frame volume, refused if GDCM found its pixel data damaged. */
VolumeType::Pointer
ReadDicomFile(const std::string & file, std::vector<std::string> & notes)
{
  GdcmWarningCapture  warnings;
  VolumeType::Pointer image = ReadMultiFrameFile(file, notes);
  RefuseDamagedPixelData(warnings, { file });
  return image;
}

LoadedVolume
LoadDicomDirectory(const std::string & directory, const std::string & seriesUID)
{
  LoadedVolume                   loaded;
  const std::vector<std::string> directoryFiles = SortedRegularFiles(directory);
  RefuseTruncatedFiles(directoryFiles, directory);
  GdcmWarningCapture quiet; // GDCM's own errors while scanning: pbdrr words the problems itself
  auto               names = itk::GDCMSeriesFileNames::New();
  names->SetUseSeriesDetails(false);
  names->SetDirectory(directory);
  const std::vector<std::string> series = names->GetSeriesUIDs();

  // The files no series took: say what they are, and refuse a directory holding damaged DICOM files (the slice it
  // held would be silently missing from a volume).
  std::set<std::string> taken;
  for (const auto & s : series)
  {
    const auto files = names->GetFileNames(s);
    taken.insert(files.begin(), files.end());
  }
  std::vector<std::string> damaged, withoutImage, otherImages, notDicom;
  for (const auto & file : directoryFiles)
  {
    if (taken.count(file))
    {
      continue;
    }
    switch (ClassifyFile(file))
    {
      case DicomContent::Damaged:
        damaged.push_back(file);
        break;
      case DicomContent::NoImage:
        withoutImage.push_back(file);
        break;
      case DicomContent::Image:
        otherImages.push_back(file);
        break;
      case DicomContent::NotDicom:
        notDicom.push_back(file);
        break;
    }
  }
  if (!damaged.empty())
  {
    Fail(std::to_string(damaged.size()) + " DICOM file(s) in " + directory +
         " cannot be read (truncated or damaged): " + JoinNames(damaged) +
         "; pbdrr does not render a series with a slice left out: repair or remove them");
  }
  if (series.empty())
  {
    Fail("no DICOM series found in directory " + directory);
  }
  if (!withoutImage.empty())
  {
    loaded.Notes.push_back("ignored " + std::to_string(withoutImage.size()) + " DICOM object(s) without an image in " +
                           directory + " (reports, structure sets, ...): " + JoinNames(withoutImage));
  }
  if (!otherImages.empty())
  {
    loaded.Notes.push_back("ignored " + std::to_string(otherImages.size()) + " DICOM image(s) in " + directory +
                           " that belong to no series: " + JoinNames(otherImages));
  }

  std::string chosen;
  if (!seriesUID.empty())
  {
    if (std::find(series.begin(), series.end(), seriesUID) == series.end())
    {
      std::string available;
      for (const auto & s : series)
      {
        available += "\n  " + s + " (" + std::to_string(names->GetFileNames(s).size()) + " files)";
      }
      Fail("series " + seriesUID + " is not in " + directory + "; available:" + available);
    }
    chosen = seriesUID;
  }
  else
  {
    size_t largest = 0;
    for (const auto & s : series)
    {
      const size_t count = names->GetFileNames(s).size();
      if (count > largest)
      {
        largest = count;
        chosen = s;
      }
    }
    if (series.size() > 1)
    {
      loaded.Notes.push_back(directory + " holds " + std::to_string(series.size()) +
                             " DICOM series; using the largest, " + chosen + " (" + std::to_string(largest) +
                             " files); choose another with --series UID");
    }
  }
  const std::vector<std::string> files = names->GetFileNames(chosen);
  if (files.size() == 1)
  {
    // One file: a multi-frame volume, or a single slice (refused as 2D).
    loaded.Image = ReadDicomFile(files[0], loaded.Notes);
  }
  else
  {
    GdcmWarningCapture warnings;
    double             spacing = 1.0;
    try
    {
      spacing = CheckSliceStack(ScanSeries(files), "the series").Spacing;
    }
    catch (const std::runtime_error & e)
    {
      // A slice cut to a few bytes no longer looks like DICOM: name such files beside the gap they leave.
      Fail(e.what() + (notDicom.empty() ? std::string()
                                        : " (" + directory + " also holds " + std::to_string(notDicom.size()) +
                                            " file(s) that are not DICOM: " + JoinNames(notDicom) + ")"));
    }
    auto reader = itk::ImageSeriesReader<VolumeType>::New();
    reader->SetImageIO(itk::GDCMImageIO::New());
    reader->SetFileNames(files);
    reader->Update();
    loaded.Image = reader->GetOutput();
    loaded.Image->DisconnectPipeline();
    auto imageSpacing = loaded.Image->GetSpacing();
    imageSpacing[2] = spacing;
    loaded.Image->SetSpacing(imageSpacing);
    RefuseDamagedPixelData(warnings, files);
  }
  const std::string name = chosen.empty() ? std::string("without a Series Instance UID") : chosen;
  loaded.Description = "DICOM series " + name + " (" + std::to_string(files.size()) + " files) in " + directory;
  return loaded;
}
} // namespace

LoadedVolume
LoadVolume(const std::string & input, const std::string & seriesUID)
{
  struct stat status;
  if (stat(input.c_str(), &status) != 0)
  {
    Fail("input " + input + " does not exist");
  }
  LoadedVolume loaded;
  try
  {
    if (S_ISDIR(status.st_mode))
    {
      loaded = LoadDicomDirectory(input, seriesUID);
    }
    else
    {
      const std::string truncation = FindDicomTruncation(input);
      if (!truncation.empty())
      {
        Fail("cannot read " + input + ": the DICOM file is truncated or damaged (" + truncation + ")");
      }
      auto io = itk::ImageIOFactory::CreateImageIO(input.c_str(), itk::IOFileModeEnum::ReadMode);
      if (!io)
      {
        Fail("cannot read " + input + ": not an image format ITK knows (DICOM directory, .mha, .nrrd, .nii, ...)");
      }
      if (dynamic_cast<itk::GDCMImageIO *>(io.GetPointer()))
      {
        // A DICOM file alone: a multi-frame volume, placed by its frame positions, or a 2D slice (refused).
        loaded.Image = ReadDicomFile(input, loaded.Notes);
      }
      else
      {
        io->SetFileName(input);
        io->ReadImageInformation();
        loaded.Image = ReadFile(input, io);
      }
      loaded.Description = "file " + input;
    }
  }
  catch (const itk::ExceptionObject & e)
  {
    Fail("cannot read " + input + ": " + e.GetDescription());
  }
  return loaded;
}
} // namespace pbdrr
