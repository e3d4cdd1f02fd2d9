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
#ifndef itkDRRImageFileChecks_h
#define itkDRRImageFileChecks_h

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <string>

namespace itk
{
/** What DRRImageFileIntegrity is made of (the engine's, not installed): a file read with its size known, the inflation
 * of a compressed stream, the comparison of the pixel data held with those promised, and the reading of each format's
 * header (itkDRRImageFileFormatChecks.cxx). Each FindXDamage() returns a sentence naming what is missing, or "" for a
 * whole file and for a form it does not check. */
namespace DRRImageFileChecks
{
constexpr uint64_t Unknown = std::numeric_limits<uint64_t>::max(); // an element type or count the check cannot size

std::string
Lowercase(std::string text);
bool
EndsWith(const std::string & text, const std::string & end);
std::string
Trim(const std::string & text);
/** The size registered for name in sizes (bytes of an element type), or Unknown. */
uint64_t
SizeOf(const std::map<std::string, uint64_t> & sizes, const std::string & name);
/** a * b, or Unknown if either is Unknown or the product overflows. */
uint64_t
Multiply(uint64_t a, uint64_t b);
/** "1 byte", "N bytes". */
std::string
Bytes(uint64_t count);
/** The file beside `header` named `name` (a relative name is relative to the header's folder). */
std::string
BesideHeader(const std::string & header, const std::string & name);
/** The whole of text as a signed integer, or fallback if it is not one (or out of range): a header's value. */
long long
ParseInteger(const std::string & text, long long fallback);
/** factor times the product of the whitespace-separated whole numbers of `numbers` (Multiply()'s overflow rule);
 * count: how many there were. A header's dimensions. */
uint64_t
ProductOf(const std::string & numbers, uint64_t factor, unsigned & count);

/** Calls visit(line, offsetAfterLine, ended) for the lines of a text header, the first at offset 0, until visit
 * returns false; ended is false for a last line that no newline ends (a header cut there). */
template <typename TVisit>
void
ForEachLine(const std::string & text, TVisit visit)
{
  for (size_t position = 0; position < text.size();)
  {
    const size_t end = text.find('\n', position);
    const bool   ended = end != std::string::npos;
    if (!visit(
          text.substr(position, ended ? end - position : std::string::npos), ended ? end + 1 : text.size(), ended) ||
        !ended)
    {
      return;
    }
    position = end + 1;
  }
}

/** A file opened for the check: its size, and reads at an offset that say whether they got every byte. */
class CheckedFile
{
public:
  explicit CheckedFile(const std::string & path) : m_Stream(path, std::ios::binary)
  {
    if (!m_Stream)
    {
      m_Error = std::strerror(errno);
      return;
    }
    m_Stream.seekg(0, std::ios::end);
    m_Size = static_cast<uint64_t>(m_Stream.tellg());
  }

  /** "" if opened, else why not. */
  const std::string &
  GetError() const
  {
    return m_Error;
  }

  uint64_t
  GetSize() const
  {
    return m_Size;
  }

  /** Reads count bytes at offset into buffer; false if the file holds fewer. */
  bool
  ReadAt(uint64_t offset, size_t count, void * buffer)
  {
    if (offset > m_Size || count > m_Size - offset)
    {
      return false;
    }
    m_Stream.clear();
    m_Stream.seekg(static_cast<std::streamoff>(offset));
    m_Stream.read(static_cast<char *>(buffer), static_cast<std::streamsize>(count));
    return static_cast<size_t>(m_Stream.gcount()) == count;
  }

  /** Up to count bytes from offset (fewer at the end of the file). */
  std::string
  ReadUpTo(uint64_t offset, size_t count)
  {
    if (offset >= m_Size)
    {
      return std::string();
    }
    std::string text(static_cast<size_t>(std::min<uint64_t>(count, m_Size - offset)), '\0');
    return ReadAt(offset, text.size(), &text[0]) ? text : std::string();
  }

private:
  std::ifstream m_Stream;
  std::string   m_Error;
  uint64_t      m_Size{ 0 };
};

/** What inflating a zlib or gzip stream found: the bytes out, whether the stream ended as its format says, and a
 * damage if it is corrupt. */
struct Inflated
{
  uint64_t    Bytes{ 0 };
  bool        Ended{ false };
  std::string Damage;
};

/** Inflates the zlib or gzip stream of `file` from `offset` to its end (gzip members one after the other, as gzip and
 * NIfTI's reader follow them), counting the bytes out; the first head->size() of them are kept in *head. */
Inflated
Inflate(CheckedFile & file, uint64_t offset, std::string * head = nullptr);

/** The damage of pixel data of `promised` bytes stored from `offset` in `file` (a data file if external), raw or
 * compressed ("" if whole). `where` names the file in the sentence ("" for the file itself). */
std::string
CheckData(CheckedFile & file, uint64_t offset, uint64_t promised, bool compressed, const std::string & where);

/** MetaImage (.mha, .mhd and its data file). */
std::string
FindMetaImageDamage(const std::string & path, CheckedFile & file);
/** NRRD (.nrrd, .nhdr and its data file). */
std::string
FindNrrdDamage(const std::string & path, CheckedFile & file);
/** NIfTI-1, NIfTI-2 and Analyze (.nii, .nii.gz, .hdr with its .img). */
std::string
FindNiftiDamage(const std::string & path, CheckedFile & file);
/** TIFF and BigTIFF: every directory, every value stored apart, every strip and tile. */
std::string
FindTiffDamage(CheckedFile & file);
} // namespace DRRImageFileChecks
} // namespace itk

#endif
