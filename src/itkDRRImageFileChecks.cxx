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

#include "itk_zlib.h"

#include <algorithm>
#include <cstdlib>
#include <sstream>
#include <vector>

namespace itk
{
namespace DRRImageFileChecks
{
std::string
Lowercase(std::string text)
{
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

bool
EndsWith(const std::string & text, const std::string & end)
{
  return text.size() >= end.size() && text.compare(text.size() - end.size(), end.size(), end) == 0;
}

std::string
Trim(const std::string & text)
{
  const size_t first = text.find_first_not_of(" \t\r\n");
  const size_t last = text.find_last_not_of(" \t\r\n");
  return first == std::string::npos ? std::string() : text.substr(first, last - first + 1);
}

uint64_t
Multiply(uint64_t a, uint64_t b)
{
  if (a == Unknown || b == Unknown || (a != 0 && b > Unknown / a))
  {
    return Unknown;
  }
  return a * b;
}

uint64_t
SizeOf(const std::map<std::string, uint64_t> & sizes, const std::string & name)
{
  const auto found = sizes.find(name);
  return found == sizes.end() ? Unknown : found->second;
}

long long
ParseInteger(const std::string & text, long long fallback)
{
  const std::string trimmed = Trim(text);
  char *            end = nullptr;
  errno = 0;
  const long long value = std::strtoll(trimmed.c_str(), &end, 10);
  return trimmed.empty() || errno == ERANGE || *end != '\0' ? fallback : value;
}

uint64_t
ProductOf(const std::string & numbers, uint64_t factor, unsigned & count)
{
  std::istringstream list(numbers);
  uint64_t           number = 0;
  count = 0;
  while (list >> number)
  {
    factor = Multiply(factor, number);
    ++count;
  }
  return factor;
}

std::string
Bytes(uint64_t count)
{
  return std::to_string(count) + (count == 1 ? " byte" : " bytes");
}

std::string
BesideHeader(const std::string & header, const std::string & name)
{
  if (!name.empty() && name[0] == '/')
  {
    return name;
  }
  const size_t slash = header.find_last_of('/');
  return slash == std::string::npos ? name : header.substr(0, slash + 1) + name;
}

Inflated
Inflate(CheckedFile & file, uint64_t offset, std::string * head)
{
  Inflated  result;
  z_stream  stream{};
  const int windowBits = 15 + 32; // zlib or gzip, told by the stream's own header
  if (inflateInit2(&stream, windowBits) != Z_OK)
  {
    result.Damage = "zlib cannot start";
    return result;
  }
  std::vector<unsigned char> in(1 << 18), out(1 << 18);
  uint64_t                   position = offset;
  size_t                     headKept = 0;
  bool                       finished = false;
  while (!finished)
  {
    if (stream.avail_in == 0)
    {
      const std::string chunk = file.ReadUpTo(position, in.size());
      if (chunk.empty())
      {
        break; // the file ended
      }
      std::memcpy(in.data(), chunk.data(), chunk.size());
      position += chunk.size();
      stream.next_in = in.data();
      stream.avail_in = static_cast<uInt>(chunk.size());
    }
    stream.next_out = out.data();
    stream.avail_out = static_cast<uInt>(out.size());
    const int    status = inflate(&stream, Z_NO_FLUSH);
    const size_t produced = out.size() - stream.avail_out;
    if (head && headKept < head->size())
    {
      const size_t kept = std::min(produced, head->size() - headKept);
      std::memcpy(&(*head)[headKept], out.data(), kept);
      headKept += kept;
    }
    result.Bytes += produced;
    if (status == Z_STREAM_END)
    {
      result.Ended = true;
      // Another gzip member may follow (its magic bytes 1f 8b); anything else after the stream is not pixel data.
      if (stream.avail_in == 0)
      {
        const std::string next = file.ReadUpTo(position, in.size());
        std::memcpy(in.data(), next.data(), next.size());
        position += next.size();
        stream.next_in = in.data();
        stream.avail_in = static_cast<uInt>(next.size());
      }
      if (stream.avail_in >= 2 && stream.next_in[0] == 0x1f && stream.next_in[1] == 0x8b)
      {
        inflateReset(&stream);
        result.Ended = false;
        continue;
      }
      finished = true;
    }
    else if (status != Z_OK && !(status == Z_BUF_ERROR && stream.avail_in == 0))
    {
      result.Damage = std::string("zlib: ") + (stream.msg ? stream.msg : "error " + std::to_string(status));
      finished = true;
    }
  }
  inflateEnd(&stream);
  if (head)
  {
    head->resize(headKept);
  }
  return result;
}

std::string
CheckData(CheckedFile & file, uint64_t offset, uint64_t promised, bool compressed, const std::string & where)
{
  const std::string holder = where.empty() ? std::string("it holds ") : "its data file " + where + " holds ";
  if (!compressed)
  {
    const uint64_t held = file.GetSize() > offset ? file.GetSize() - offset : 0;
    if (held < promised)
    {
      return holder + Bytes(held) + " of pixel data" + (offset ? " after its header (" + Bytes(offset) + ")" : "") +
             " where its header promises " + std::to_string(promised) + ": the file is truncated";
    }
    return std::string();
  }
  const Inflated inflated = Inflate(file, offset);
  if (!inflated.Damage.empty())
  {
    return (where.empty() ? std::string("its") : "the data file " + where + "'s") +
           " compressed pixel data are damaged (" + inflated.Damage + ")";
  }
  if (!inflated.Ended)
  {
    return (where.empty() ? std::string("its") : "the data file " + where + "'s") +
           " compressed pixel data are cut short (" + Bytes(inflated.Bytes) + " of " + std::to_string(promised) +
           " inflated): the file is truncated";
  }
  if (inflated.Bytes < promised)
  {
    return (where.empty() ? std::string("its") : "the data file " + where + "'s") + " compressed stream holds " +
           Bytes(inflated.Bytes) + " of pixel data where its header promises " + std::to_string(promised);
  }
  return std::string();
}
} // namespace DRRImageFileChecks
} // namespace itk
