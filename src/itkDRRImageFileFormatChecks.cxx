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
#include "itkDRRImageFileChecks.h"

#include <algorithm>
#include <cstring>
#include <map>
#include <set>
#include <vector>

namespace itk
{
namespace DRRImageFileChecks
{
namespace
{
// --- MetaImage ------------------------------------------------------------------------------------------------------

uint64_t
MetaElementBytes(std::string type)
{
  if (EndsWith(type, "_ARRAY"))
  {
    type = type.substr(0, type.size() - 6);
  }
  static const std::map<std::string, uint64_t> sizes{
    { "MET_CHAR", 1 },      { "MET_UCHAR", 1 },      { "MET_SHORT", 2 }, { "MET_USHORT", 2 },
    { "MET_INT", 4 },       { "MET_UINT", 4 },       { "MET_LONG", 4 },  { "MET_ULONG", 4 },
    { "MET_LONG_LONG", 8 }, { "MET_ULONG_LONG", 8 }, { "MET_FLOAT", 4 }, { "MET_DOUBLE", 8 }
  };
  return SizeOf(sizes, type);
}

} // namespace

std::string
FindMetaImageDamage(const std::string & path, CheckedFile & file)
{
  // The header: "Key = Value" lines, ElementDataFile the last; the data follow its line (LOCAL).
  std::map<std::string, std::string> fields;
  size_t                             dataOffset = std::string::npos;
  bool                               lastLineCut = false;
  ForEachLine(file.ReadUpTo(0, 1 << 16), [&](const std::string & line, size_t next, bool ended) {
    const size_t equals = line.find('=');
    if (equals == std::string::npos)
    {
      return true;
    }
    const std::string key = Trim(line.substr(0, equals));
    fields[key] = Trim(line.substr(equals + 1));
    if (key != "ElementDataFile")
    {
      return true;
    }
    lastLineCut = !ended;
    dataOffset = ended ? next : dataOffset;
    return false;
  });
  if (lastLineCut)
  {
    return "its header ends in its last line (ElementDataFile, " + Bytes(file.GetSize()) + "): the file is truncated";
  }
  if (dataOffset == std::string::npos)
  {
    return "its header ends before ElementDataFile (" + Bytes(file.GetSize()) + "): the file is truncated";
  }
  unsigned count = 0;
  uint64_t promised = ProductOf(fields["DimSize"], MetaElementBytes(fields["ElementType"]), count);
  if (fields.count("ElementNumberOfChannels"))
  {
    const long long channels = ParseInteger(fields["ElementNumberOfChannels"], -1);
    promised = channels < 1 ? Unknown : Multiply(promised, static_cast<uint64_t>(channels));
  }
  const std::string data = fields["ElementDataFile"];
  if (count == 0 || promised == Unknown || data.rfind("LIST", 0) == 0 || data.find('%') != std::string::npos)
  {
    return std::string(); // not sized, or data in several files: MetaIO reports what it misses there
  }
  const bool compressed = Lowercase(fields["CompressedData"]) == "true";
  if (data == "LOCAL")
  {
    return CheckData(file, dataOffset, promised, compressed, "");
  }
  const std::string dataPath = BesideHeader(path, data);
  CheckedFile       dataFile(dataPath);
  if (!dataFile.GetError().empty())
  {
    return "cannot open its data file " + dataPath + ": " + dataFile.GetError();
  }
  const long long headerSize = ParseInteger(fields["HeaderSize"], 0);
  if (headerSize < 0 && !compressed)
  {
    return CheckData(dataFile, 0, promised, false, dataPath); // the data are the file's last bytes
  }
  return CheckData(dataFile, static_cast<uint64_t>(std::max(0LL, headerSize)), promised, compressed, dataPath);
}

namespace
{

// --- NRRD -----------------------------------------------------------------------------------------------------------

uint64_t
NrrdTypeBytes(const std::string & type)
{
  static const std::map<std::string, uint64_t> sizes{ { "signed char", 1 },
                                                      { "int8", 1 },
                                                      { "int8_t", 1 },
                                                      { "uchar", 1 },
                                                      { "unsigned char", 1 },
                                                      { "uint8", 1 },
                                                      { "uint8_t", 1 },
                                                      { "short", 2 },
                                                      { "short int", 2 },
                                                      { "signed short", 2 },
                                                      { "signed short int", 2 },
                                                      { "int16", 2 },
                                                      { "int16_t", 2 },
                                                      { "ushort", 2 },
                                                      { "unsigned short", 2 },
                                                      { "unsigned short int", 2 },
                                                      { "uint16", 2 },
                                                      { "uint16_t", 2 },
                                                      { "int", 4 },
                                                      { "signed int", 4 },
                                                      { "int32", 4 },
                                                      { "int32_t", 4 },
                                                      { "uint", 4 },
                                                      { "unsigned int", 4 },
                                                      { "uint32", 4 },
                                                      { "uint32_t", 4 },
                                                      { "float", 4 },
                                                      { "longlong", 8 },
                                                      { "long long", 8 },
                                                      { "long long int", 8 },
                                                      { "signed long long", 8 },
                                                      { "signed long long int", 8 },
                                                      { "int64", 8 },
                                                      { "int64_t", 8 },
                                                      { "ulonglong", 8 },
                                                      { "unsigned long long", 8 },
                                                      { "unsigned long long int", 8 },
                                                      { "uint64", 8 },
                                                      { "uint64_t", 8 },
                                                      { "double", 8 } };
  return SizeOf(sizes, type);
}

} // namespace

std::string
FindNrrdDamage(const std::string & path, CheckedFile & file)
{
  // The header: a magic line, then "field: value" lines to a blank line (the data follow it) or the end of a .nhdr.
  std::map<std::string, std::string> fields;
  size_t                             dataOffset = std::string::npos;
  ForEachLine(file.ReadUpTo(0, 1 << 16), [&](const std::string & line, size_t next, bool ended) {
    if (!ended)
    {
      return false; // a line no newline ends is not the header's
    }
    if (Trim(line).empty())
    {
      dataOffset = next;
      return false;
    }
    const size_t colon = line.find(": ");
    if (line[0] != '#' && colon != std::string::npos && line.compare(colon, 3, ":= ") != 0)
    {
      std::string key = Lowercase(Trim(line.substr(0, colon)));
      key.erase(std::remove(key.begin(), key.end(), ' '), key.end()); // "data file" and "datafile" alike
      fields[key] = Trim(line.substr(colon + 2));
    }
    return true;
  });
  const std::string data = fields["datafile"];
  if (data.empty() && dataOffset == std::string::npos)
  {
    return "its header has no end (the blank line before the data; " + Bytes(file.GetSize()) +
           "): the file is truncated";
  }
  unsigned          count = 0;
  const uint64_t    promised = ProductOf(fields["sizes"], NrrdTypeBytes(fields["type"]), count);
  const std::string encoding = Lowercase(fields["encoding"]);
  const bool        compressed = encoding == "gzip" || encoding == "gz";
  const long long   byteSkip = ParseInteger(fields["byteskip"], 0);
  const long long   lineSkip = ParseInteger(fields["lineskip"], 0);
  if (count == 0 || promised == Unknown || !(compressed || encoding == "raw") || lineSkip != 0 ||
      data.rfind("LIST", 0) == 0 || data.find(' ') != std::string::npos)
  {
    return std::string(); // not sized, text or bzip2, or data in several files: teem reports what it misses there
  }
  CheckedFile       dataFile(data.empty() ? path : BesideHeader(path, data));
  const std::string where = data.empty() ? std::string() : BesideHeader(path, data);
  if (!dataFile.GetError().empty())
  {
    return "cannot open its data file " + where + ": " + dataFile.GetError();
  }
  const uint64_t start = data.empty() ? dataOffset : 0;
  if (byteSkip < 0 && !compressed)
  {
    return CheckData(dataFile, 0, promised, false, where); // the data are the file's last bytes
  }
  // A byte skip counts the file's bytes when raw, the inflated ones when compressed.
  const uint64_t skip = static_cast<uint64_t>(byteSkip);
  return compressed ? CheckData(dataFile, start, promised > Unknown - skip ? Unknown : promised + skip, true, where)
                    : CheckData(dataFile, start + skip, promised, false, where);
}

namespace
{

// --- NIfTI ----------------------------------------------------------------------------------------------------------

template <typename T>
T
ReadValue(const std::string & header, size_t offset, bool swapped)
{
  T value;
  std::memcpy(&value, header.data() + offset, sizeof(T));
  if (swapped)
  {
    auto * bytes = reinterpret_cast<unsigned char *>(&value);
    std::reverse(bytes, bytes + sizeof(T));
  }
  return value;
}

/** The voxels' bytes and their offset as a NIfTI-1, NIfTI-2 or Analyze header says; false if it is none of them. */
bool
ReadNiftiHeader(const std::string & header, uint64_t & promised, uint64_t & offset)
{
  if (header.size() < 348)
  {
    return false;
  }
  const int32_t sizeofHeader = ReadValue<int32_t>(header, 0, false);
  const int32_t swappedSize = ReadValue<int32_t>(header, 0, true);
  const bool    two = sizeofHeader == 540 || swappedSize == 540;
  const bool    swapped = swappedSize == 348 || swappedSize == 540;
  if (!two && sizeofHeader != 348 && !swapped)
  {
    return false;
  }
  if (two && header.size() < 540)
  {
    return false;
  }
  const int64_t dimensions = two ? ReadValue<int64_t>(header, 16, swapped) : ReadValue<int16_t>(header, 40, swapped);
  const int     bitpix = two ? ReadValue<int16_t>(header, 14, swapped) : ReadValue<int16_t>(header, 72, swapped);
  if (dimensions < 1 || dimensions > 7 || bitpix <= 0 || bitpix % 8 != 0)
  {
    return false;
  }
  promised = static_cast<uint64_t>(bitpix / 8);
  for (int64_t d = 1; d <= dimensions; ++d)
  {
    const int64_t extent = two ? ReadValue<int64_t>(header, static_cast<size_t>(16 + 8 * d), swapped)
                               : ReadValue<int16_t>(header, static_cast<size_t>(40 + 2 * d), swapped);
    if (extent < 1)
    {
      return false;
    }
    promised = Multiply(promised, static_cast<uint64_t>(extent));
  }
  const double voxOffset =
    two ? static_cast<double>(ReadValue<int64_t>(header, 168, swapped)) : ReadValue<float>(header, 108, swapped);
  if (!(voxOffset >= 0.0 && voxOffset < 1e18) || promised == Unknown)
  {
    return false;
  }
  offset = static_cast<uint64_t>(voxOffset);
  return true;
}

} // namespace

std::string
FindNiftiDamage(const std::string & path, CheckedFile & file)
{
  const std::string lower = Lowercase(path);
  const bool        gzipped = EndsWith(lower, ".gz");
  std::string       header(540, '\0');
  Inflated          inflated;
  if (gzipped)
  {
    inflated = Inflate(file, 0, &header);
    if (!inflated.Damage.empty())
    {
      return "its gzip stream is damaged (" + inflated.Damage + ")";
    }
  }
  else
  {
    header = file.ReadUpTo(0, 540);
  }
  uint64_t promised = 0, offset = 0;
  if (!ReadNiftiHeader(header, promised, offset))
  {
    return header.size() < 348 ? "it holds " + Bytes(gzipped ? inflated.Bytes : file.GetSize()) +
                                   ", fewer than a NIfTI header's 348: the file is truncated"
                               : std::string(); // not a header this check reads: NIfTI's reader words it
  }
  if (EndsWith(lower, ".hdr") || EndsWith(lower, ".hdr.gz"))
  {
    // A pair: the voxels in the .img beside the .hdr (or .img.gz), from vox_offset.
    std::string image = path.substr(0, path.size() - (gzipped ? 7 : 4)) + ".img";
    CheckedFile plain(image);
    if (!plain.GetError().empty())
    {
      CheckedFile packed(image + ".gz");
      if (!packed.GetError().empty())
      {
        return "cannot open its image file " + image + ": " + plain.GetError();
      }
      const Inflated voxels = Inflate(packed, 0);
      return !voxels.Damage.empty() || !voxels.Ended || voxels.Bytes < offset + promised
               ? "its image file " + image + ".gz is truncated or damaged (" + Bytes(voxels.Bytes) + " of " +
                   std::to_string(offset + promised) + " inflated)"
               : std::string();
    }
    return CheckData(plain, offset, promised, false, image);
  }
  if (!gzipped)
  {
    return CheckData(file, offset, promised, false, "");
  }
  if (!inflated.Ended || inflated.Bytes < offset + promised)
  {
    return "its gzip stream " + std::string(inflated.Ended ? "holds " : "is cut short after ") +
           Bytes(inflated.Bytes > offset ? inflated.Bytes - offset : 0) + " of pixel data where its header promises " +
           std::to_string(promised) + ": the file is truncated";
  }
  return std::string();
}

namespace
{
// --- TIFF -----------------------------------------------------------------------------------------------------------

/** Reads an unsigned integer of `width` bytes (2, 4 or 8) in the file's byte order. */
uint64_t
TiffInteger(const unsigned char * bytes, unsigned width, bool bigEndian)
{
  uint64_t value = 0;
  for (unsigned k = 0; k < width; ++k)
  {
    const unsigned char byte = bigEndian ? bytes[k] : bytes[width - 1 - k];
    value = (value << 8) | byte;
  }
  return value;
}

} // namespace

std::string
FindTiffDamage(CheckedFile & file)
{
  unsigned char head[16];
  if (!file.ReadAt(0, 8, head))
  {
    return "it holds " + Bytes(file.GetSize()) + ", fewer than a TIFF header's 8: the file is truncated";
  }
  const bool big = head[0] == 'M' && head[1] == 'M';
  if (!(big || (head[0] == 'I' && head[1] == 'I')))
  {
    return std::string(); // not TIFF: its reader words it
  }
  const uint64_t version = TiffInteger(head + 2, 2, big);
  const bool     bigTiff = version == 43;
  if (version != 42 && !bigTiff)
  {
    return std::string();
  }
  if (bigTiff && !file.ReadAt(0, 16, head))
  {
    return "it holds " + Bytes(file.GetSize()) + ", fewer than a BigTIFF header's 16: the file is truncated";
  }
  const unsigned     offsetWidth = bigTiff ? 8 : 4;
  const unsigned     countWidth = bigTiff ? 8 : 2;
  const unsigned     entryWidth = bigTiff ? 20 : 12;
  uint64_t           directory = bigTiff ? TiffInteger(head + 8, 8, big) : TiffInteger(head + 4, 4, big);
  std::set<uint64_t> visited;
  for (unsigned index = 0; directory != 0; ++index)
  {
    if (!visited.insert(directory).second)
    {
      return "its directory " + std::to_string(index) + " points back to an earlier one: the file is damaged";
    }
    unsigned char countBytes[8];
    if (!file.ReadAt(directory, countWidth, countBytes))
    {
      return "its directory " + std::to_string(index) + " (at byte " + std::to_string(directory) +
             ") is past the end of the file (" + Bytes(file.GetSize()) + "): the file is truncated";
    }
    const uint64_t             entries = TiffInteger(countBytes, countWidth, big);
    std::vector<unsigned char> table(static_cast<size_t>(std::min<uint64_t>(entries, 1 << 16)) * entryWidth +
                                     offsetWidth);
    if (entries > (1 << 16) || !file.ReadAt(directory + countWidth, table.size(), table.data()))
    {
      return "its directory " + std::to_string(index) + " (" + std::to_string(entries) + " entries at byte " +
             std::to_string(directory) + ") is cut by the end of the file (" + Bytes(file.GetSize()) +
             "): the file is truncated";
    }
    // Every value stored apart from its entry inside the file; and the pixel data's places: strip or tile offsets
    // (273, 324) and byte counts (279, 325).
    std::map<unsigned, std::vector<uint64_t>> arrays;
    for (uint64_t e = 0; e < entries; ++e)
    {
      const unsigned char * entry = table.data() + e * entryWidth;
      const unsigned        tag = static_cast<unsigned>(TiffInteger(entry, 2, big));
      const unsigned        type = static_cast<unsigned>(TiffInteger(entry + 2, 2, big));
      static const unsigned typeBytes[19] = { 0, 1, 1, 2, 4, 8, 1, 1, 2, 4, 8, 4, 8, 4, 0, 0, 8, 8, 8 };
      const uint64_t        valueBytes =
        Multiply(TiffInteger(entry + 4, countWidth == 8 ? 8 : 4, big), type < 19 ? typeBytes[type] : 0);
      const uint64_t valueOffset = TiffInteger(entry + 4 + (bigTiff ? 8 : 4), offsetWidth, big);
      if (valueBytes > offsetWidth &&
          (valueBytes == Unknown || valueOffset > file.GetSize() || valueBytes > file.GetSize() - valueOffset))
      {
        return "its directory " + std::to_string(index) + "'s tag " + std::to_string(tag) + " (" + Bytes(valueBytes) +
               " at byte " + std::to_string(valueOffset) + ") is past the end of the file (" + Bytes(file.GetSize()) +
               "): the file is truncated";
      }
      if (tag != 273 && tag != 279 && tag != 324 && tag != 325)
      {
        continue;
      }
      const unsigned width = type == 3 ? 2 : type == 4 ? 4 : type == 16 ? 8 : 0;
      const uint64_t n = TiffInteger(entry + 4, countWidth == 8 ? 8 : 4, big);
      if (width == 0 || n > (1u << 24))
      {
        return std::string(); // a form this check does not read: libtiff words it
      }
      std::vector<unsigned char> values(static_cast<size_t>(n) * width);
      const unsigned char *      field = entry + 4 + (bigTiff ? 8 : 4);
      if (values.size() <= offsetWidth)
      {
        std::memcpy(values.data(), field, values.size());
      }
      else if (!file.ReadAt(TiffInteger(field, offsetWidth, big), values.size(), values.data()))
      {
        return "its directory " + std::to_string(index) + "'s list of pixel data places is past the end of the file (" +
               Bytes(file.GetSize()) + "): the file is truncated";
      }
      for (uint64_t k = 0; k < n; ++k)
      {
        arrays[tag].push_back(TiffInteger(values.data() + k * width, width, big));
      }
    }
    for (const auto & pair : { std::make_pair(273u, 279u), std::make_pair(324u, 325u) })
    {
      const auto & offsets = arrays[pair.first];
      const auto & counts = arrays[pair.second];
      for (size_t k = 0; k < std::min(offsets.size(), counts.size()); ++k)
      {
        if (offsets[k] > file.GetSize() || counts[k] > file.GetSize() - offsets[k])
        {
          return std::string("its directory ") + std::to_string(index) + "'s " +
                 (pair.first == 273 ? "strip " : "tile ") + std::to_string(k) + " (bytes " +
                 std::to_string(offsets[k]) + " to " + std::to_string(offsets[k] + counts[k]) +
                 ") is past the end of the file (" + Bytes(file.GetSize()) + "): the file is truncated";
        }
      }
    }
    directory = TiffInteger(table.data() + entries * entryWidth, offsetWidth, big);
  }
  return std::string();
}
} // namespace DRRImageFileChecks
} // namespace itk
