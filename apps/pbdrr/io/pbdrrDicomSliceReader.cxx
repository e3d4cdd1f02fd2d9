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
#include "pbdrrDicomSliceReader.h"

#include "itkGDCMImageIO.h"
#include "itkImageSeriesReader.h"
#include "itkMath.h"
#include "itkMetaDataObject.h"
#include "itkOutputWindow.h"
#include "gdcmImageChangeTransferSyntax.h"
#include "gdcmImageReader.h"
#include "gdcmRescaler.h"

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstring>
#include <mutex>
#include <sstream>
#include <type_traits>

#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

namespace pbdrr
{
namespace
{
using OriginType = itk::Point<double, 3>;

/** The buffers a thread reuses from file to file. */
struct Scratch
{
  std::vector<char> Stored; // a slice's stored values, when they are rescaled
  std::vector<char> Values; // a slice's values in GDCMImageIO's type, when that is not the volume's
};

template <typename T>
T *
Resized(std::vector<char> & buffer, size_t count)
{
  buffer.resize(count * sizeof(T));
  return reinterpret_cast<T *>(buffer.data());
}

/** Whether `image` is a slice this reader decodes as GDCMImageIO does: one 2D frame of the volume's rows and columns,
 * one MONOCHROME2 sample of 8, 16 or 32 bits per pixel (GDCMImageIO inverts MONOCHROME1, expands palettes, ...),
 * uncompressed or JPEG 2000 (OpenJPEG keeps no state shared between threads). */
bool
IsPlainSlice(const gdcm::Image & image, const itk::Size<3> & size)
{
  const gdcm::PixelFormat &    format = image.GetPixelFormat();
  const gdcm::TransferSyntax & syntax = image.GetTransferSyntax();
  const unsigned short         bits = format.GetBitsAllocated();
  const bool decodable = !syntax.IsEncapsulated() || syntax == gdcm::TransferSyntax::JPEG2000Lossless ||
                         syntax == gdcm::TransferSyntax::JPEG2000;
  return image.GetNumberOfDimensions() == 2 && image.GetDimension(0) == size[0] && image.GetDimension(1) == size[1] &&
         image.GetPhotometricInterpretation() == gdcm::PhotometricInterpretation::MONOCHROME2 &&
         format.GetSamplesPerPixel() == 1 && image.GetPlanarConfiguration() == 0 &&
         (bits == 8 || bits == 16 || bits == 32) && decodable;
}

/** The stored values of a slice of 16-bit pixels stored uncompressed in little-endian order (nearly every CT): what
 * gdcm::Bitmap::GetBuffer gives, without the copies through string streams it makes when Bits Stored is below Bits
 * Allocated (a fifth of the time of a whole read). Its unused high bits are cleared, or set for negative signed
 * values, as gdcm::ImageCodec::DoOverlayCleanup does. False, having written nothing, for any other slice. */
bool
DecodeNative16(const gdcm::Image & image, char * stored, size_t bytes)
{
#ifdef GDCM_WORDS_BIGENDIAN
  return false;
#else
  const gdcm::PixelFormat &    format = image.GetPixelFormat();
  const gdcm::TransferSyntax & syntax = image.GetTransferSyntax();
  const gdcm::ByteValue *      pixels = image.GetDataElement().GetByteValue();
  const unsigned short         bitsStored = format.GetBitsStored();
  const bool                   littleEndian =
    syntax == gdcm::TransferSyntax::ImplicitVRLittleEndian || syntax == gdcm::TransferSyntax::ExplicitVRLittleEndian;
  if (!littleEndian || image.GetNeedByteSwap() || pixels == nullptr || pixels->GetLength() < bytes ||
      format.GetBitsAllocated() != 16 || bytes % 2 != 0 ||
      image.GetPhotometricInterpretation() != gdcm::PhotometricInterpretation::MONOCHROME2 || bitsStored < 1 ||
      bitsStored > 16 || format.GetHighBit() != bitsStored - 1)
  {
    return false;
  }
  const char * in = pixels->GetPointer();
  if (bitsStored == 16 || !(image.AreOverlaysInPixelData() || image.UnusedBitsPresentInPixelData()))
  {
    std::memcpy(stored, in, bytes);
    return true;
  }
  const auto used = static_cast<uint16_t>(0xffffu >> (16 - bitsStored));
  const auto sign = static_cast<uint16_t>(1u << (bitsStored - 1));
  const bool signedValues = format.GetPixelRepresentation() != 0;
  for (size_t b = 0; b < bytes; b += 2)
  {
    uint16_t value;
    std::memcpy(&value, in + b, 2);
    value = signedValues && (value & sign) ? static_cast<uint16_t>(value | ~used) : static_cast<uint16_t>(value & used);
    std::memcpy(stored + b, &value, 2);
  }
  return true;
#endif
}

/** A slice's values as GDCMImageIO::Read gives them, in its type TValue (the stored type, or the type GDCM's rescaler
 * fits the rescaled range into), then as ImageFileReader converts them to the volume's (static_cast). They are written
 * straight into the volume when TValue is its pixel type, else through the thread's scratch buffer. False if GDCM
 * cannot decode the slice, or decodes it to another pixel format than its header's (GDCMImageIO would then read its
 * values in a type that is not theirs). */
template <typename TValue, typename TPixel>
bool
ReadSliceValues(gdcm::Image & image, TPixel * slice, size_t pixels, Scratch & scratch)
{
  const gdcm::PixelFormat format = image.GetPixelFormat();
  const size_t            bytes = image.GetBufferLength();
  const double            slope = image.GetSlope();
  const double            intercept = image.GetIntercept();
  const bool              rescaled = slope != 1.0 || intercept != 0.0;
  constexpr bool          inPlace = std::is_same<TValue, TPixel>::value;
  if (bytes != pixels * format.GetPixelSize() || (!rescaled && format.GetPixelSize() != sizeof(TValue)))
  {
    return false;
  }
  if (image.GetTransferSyntax().IsEncapsulated())
  {
    // Decompressed first, as GDCMImageIO does, then decoded as uncompressed slices are.
    gdcm::ImageChangeTransferSyntax change;
    change.SetInput(image);
    change.SetTransferSyntax(gdcm::TransferSyntax::ImplicitVRLittleEndian);
    if (!change.Change())
    {
      return false;
    }
    image = change.GetOutput();
  }
  TValue * values = inPlace ? reinterpret_cast<TValue *>(slice) : Resized<TValue>(scratch.Values, pixels);
  char *   stored = rescaled ? Resized<char>(scratch.Stored, bytes) : reinterpret_cast<char *>(values);
  if ((!DecodeNative16(image, stored, bytes) && !image.GetBuffer(stored)) || !(image.GetPixelFormat() == format))
  {
    return false;
  }
  if (rescaled)
  {
    gdcm::Rescaler rescaler;
    rescaler.SetIntercept(intercept);
    rescaler.SetSlope(slope);
    rescaler.SetPixelFormat(format);
    rescaler.ComputeInterceptSlopePixelType();
    if (!rescaler.Rescale(reinterpret_cast<char *>(values), stored, bytes))
    {
      return false;
    }
  }
  if (!inPlace)
  {
    std::transform(values, values + pixels, slice, [](TValue v) { return static_cast<TPixel>(v); });
  }
  return true;
}

/** GDCMImageIO's type for a slice's values: the stored type, or with a slope or intercept the type GDCM's rescaler
 * fits the rescaled range into (e.g. int16 for unsigned 12-bit values and an intercept of -1024). */
gdcm::PixelFormat::ScalarType
ValueType(const gdcm::Image & image)
{
  const gdcm::PixelFormat & format = image.GetPixelFormat();
  if (image.GetSlope() == 1.0 && image.GetIntercept() == 0.0)
  {
    return format.GetScalarType();
  }
  gdcm::Rescaler rescaler;
  rescaler.SetIntercept(image.GetIntercept());
  rescaler.SetSlope(image.GetSlope());
  rescaler.SetPixelFormat(format);
  const gdcm::PixelFormat::ScalarType type = rescaler.ComputeInterceptSlopePixelType();
  // GDCMImageIO refuses a type smaller than the stored one.
  return format.GetScalarType() > type ? gdcm::PixelFormat::UNKNOWN : type;
}

/** Reads one file into its slice of the volume (`size` its size), and its origin as GDCMImageIO reads it. */
template <typename TPixel>
bool
ReadSlice(const std::string & file, const itk::Size<3> & size, TPixel * slice, Scratch & scratch, OriginType & origin)
{
  gdcm::ImageReader reader;
  reader.SetFileName(file.c_str());
  if (!reader.Read() || !IsPlainSlice(reader.GetImage(), size))
  {
    return false;
  }
  gdcm::Image & image = reader.GetImage();
  for (unsigned int i = 0; i < 3; ++i)
  {
    origin[i] = image.GetOrigin(i);
  }
  const size_t pixels = size[0] * size[1];
  // GDCMImageIO's component type for each of GDCM's types.
  switch (ValueType(image))
  {
    case gdcm::PixelFormat::INT8:
      return ReadSliceValues<char>(image, slice, pixels, scratch);
    case gdcm::PixelFormat::UINT8:
      return ReadSliceValues<unsigned char>(image, slice, pixels, scratch);
    case gdcm::PixelFormat::INT12:
    case gdcm::PixelFormat::INT16:
      return ReadSliceValues<short>(image, slice, pixels, scratch);
    case gdcm::PixelFormat::UINT12:
    case gdcm::PixelFormat::UINT16:
      return ReadSliceValues<unsigned short>(image, slice, pixels, scratch);
    case gdcm::PixelFormat::INT32:
      return ReadSliceValues<int>(image, slice, pixels, scratch);
    case gdcm::PixelFormat::UINT32:
      return ReadSliceValues<unsigned int>(image, slice, pixels, scratch);
    case gdcm::PixelFormat::FLOAT32:
      return ReadSliceValues<float>(image, slice, pixels, scratch);
    case gdcm::PixelFormat::FLOAT64:
      return ReadSliceValues<double>(image, slice, pixels, scratch);
    default:
      return false;
  }
}

/** Asks Linux to back a large buffer, still untouched, with 2 MB pages: the threads that first write to it then take
 * one page fault per 2 MB, not per 4 kB (the chest's 144 MB took 35000 faults, a quarter of its decoding time). A hint
 * only: elsewhere, or where transparent huge pages are off, nothing changes. */
void
AdviseHugePages(void * buffer, size_t bytes)
{
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  const auto page = static_cast<uintptr_t>(sysconf(_SC_PAGESIZE));
  const auto start = (reinterpret_cast<uintptr_t>(buffer) + page - 1) / page * page;
  const auto end = (reinterpret_cast<uintptr_t>(buffer) + bytes) / page * page;
  if (end > start)
  {
    madvise(reinterpret_cast<void *>(start), end - start, MADV_HUGEPAGE);
  }
#else
  (void)buffer;
  (void)bytes;
#endif
}

/** An allocated volume on the grid itk::ImageSeriesReader gives `files`, from the first and last files' headers (it
 * is that reader's own computation, tilted grids included); null unless it is one 2D slice per file. */
template <typename TVolume>
typename TVolume::Pointer
AllocateSeriesGrid(const std::vector<std::string> & files, bool forceOrthogonalDirection)
{
  auto series = itk::ImageSeriesReader<TVolume>::New();
  series->SetImageIO(itk::GDCMImageIO::New());
  series->SetFileNames(files);
  series->SetForceOrthogonalDirection(forceOrthogonalDirection);
  try
  {
    series->UpdateOutputInformation();
  }
  catch (const itk::ExceptionObject &)
  {
    return nullptr;
  }
  const typename TVolume::RegionType region = series->GetOutput()->GetLargestPossibleRegion();
  if (files.size() < 2 || region.GetSize(2) != files.size())
  {
    return nullptr;
  }
  auto volume = TVolume::New();
  volume->CopyInformation(series->GetOutput());
  volume->SetRegions(region);
  volume->Allocate();
  AdviseHugePages(volume->GetBufferPointer(), region.GetNumberOfPixels() * sizeof(typename TVolume::PixelType));
  return volume;
}

/** Reads file i into slice i of `volume`, on the threads of `threader`, files handed out one at a time (a thread
 * slowed down by other work reads fewer). False if a file is not one this reader decodes. */
template <typename TVolume>
bool
ReadSlicesInParallel(const std::vector<std::string> & files,
                     TVolume &                        volume,
                     std::vector<OriginType> &        origins,
                     const LoadProgress &             progress,
                     itk::MultiThreaderBase &         threader)
{
  const itk::Size<3>  size = volume.GetLargestPossibleRegion().GetSize();
  const size_t        pixelsPerSlice = size[0] * size[1];
  std::atomic<size_t> next{ 0 };
  std::atomic<bool>   failed{ false };
  std::mutex          progressMutex;
  size_t              read = 0;
  // GDCM's global settings (e.g. that Rescale Slope and Intercept apply) are as GDCMImageIO left them when it read the
  // first and last headers; the threads only read them.
  const auto work = [&](itk::SizeValueType) {
    Scratch scratch;
    try
    {
      for (size_t i = next++; i < files.size() && !failed; i = next++)
      {
        if (!ReadSlice(files[i], size, volume.GetBufferPointer() + i * pixelsPerSlice, scratch, origins[i]))
        {
          failed = true;
        }
        else if (progress)
        {
          const std::lock_guard<std::mutex> lock(progressMutex);
          progress(++read, files.size());
        }
      }
    }
    catch (...)
    {
      failed = true; // e.g. out of memory: ImageSeriesReader reports it
    }
  };
  const auto workers = std::max<size_t>(1, std::min<size_t>(files.size(), threader.GetMaximumNumberOfThreads()));
  if (workers == 1)
  {
    work(0);
  }
  else
  {
    threader.ParallelizeArray(0, workers, work, nullptr);
  }
  return !failed;
}

/** ImageSeriesReader's check of each step from slice to slice against the spacing it took from the first and last
 * slices: the largest deviation goes into the volume's dictionary, and a warning when above 1e-4 of the spacing. */
template <typename TVolume>
void
ReportNonUniformSampling(TVolume & volume, const std::vector<OriginType> & origins)
{
  if (itk::Math::AlmostEquals((origins.back() - origins.front()).GetNorm(), 0.0))
  {
    return; // no spacing from the positions: ImageSeriesReader checks nothing
  }
  const double spacing = volume.GetSpacing()[2];
  double       deviation = 0.0;
  for (size_t i = 1; i < origins.size(); ++i)
  {
    const double step = (origins[i] - origins[i - 1]).GetNorm();
    if (!itk::Math::AlmostEquals(step, spacing))
    {
      deviation = std::max(deviation, itk::Math::abs(spacing - step));
    }
  }
  if (deviation > 1e-4 * spacing && itk::Object::GetGlobalWarningDisplay())
  {
    std::ostringstream text;
    text << "WARNING: In " __FILE__ ", line " << __LINE__ << "\nImageSeriesReader (" << &volume
         << "): Non uniform sampling or missing slices detected,  maximum nonuniformity:" << deviation << "\n\n";
    itk::OutputWindowDisplayWarningText(text.str().c_str());
  }
  if (deviation > 0.0)
  {
    itk::EncapsulateMetaData<double>(volume.GetMetaDataDictionary(), "ITK_non_uniform_sampling_deviation", deviation);
  }
}
} // namespace

template <typename TVolume>
typename TVolume::Pointer
ReadDicomSlices(const std::vector<std::string> & files,
                bool                             forceOrthogonalDirection,
                const LoadProgress &             progress,
                itk::MultiThreaderBase *         threader)
{
  typename TVolume::Pointer volume = AllocateSeriesGrid<TVolume>(files, forceOrthogonalDirection);
  if (!volume)
  {
    return nullptr;
  }
  itk::MultiThreaderBase::Pointer ownThreader;
  if (threader == nullptr)
  {
    ownThreader = itk::MultiThreaderBase::New();
    threader = ownThreader.GetPointer();
  }
  std::vector<OriginType> origins(files.size());
  if (!ReadSlicesInParallel(files, *volume, origins, progress, *threader))
  {
    return nullptr;
  }
  ReportNonUniformSampling(*volume, origins);
  return volume;
}

template HUVolumeType::Pointer
ReadDicomSlices<HUVolumeType>(const std::vector<std::string> &, bool, const LoadProgress &, itk::MultiThreaderBase *);
template VolumeType::Pointer
ReadDicomSlices<VolumeType>(const std::vector<std::string> &, bool, const LoadProgress &, itk::MultiThreaderBase *);
} // namespace pbdrr
