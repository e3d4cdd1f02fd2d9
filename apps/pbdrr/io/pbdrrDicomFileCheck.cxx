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
#include "pbdrrDicomFileCheck.h"

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

namespace pbdrr
{
namespace
{
constexpr uint32_t undefinedLength = 0xFFFFFFFFu;
constexpr unsigned maximumDepth = 32; // nested sequences; deeper is not a CT header

/** Thrown when a header promises bytes the file does not have. */
struct Truncated
{
  std::string What;
};

/** Thrown when the bytes are not an encoding this walker knows: GDCM decides then. */
struct Unknown
{};

std::string
TagName(uint16_t group, uint16_t element)
{
  char name[16];
  std::snprintf(name, sizeof(name), "(%04x,%04x)", group, element);
  return name;
}

/** Little-endian element headers of a file, read on demand (values are skipped, never read). */
class HeaderWalker
{
public:
  HeaderWalker(std::ifstream & stream, uint64_t size) : m_Stream(stream), m_Size(size) {}

  /** Walks the meta group (always explicit little endian) from offset 132; returns the transfer syntax UID. */
  std::string
  WalkMetaGroup()
  {
    m_Position = 132;
    std::string syntax;
    for (;;)
    {
      if (m_Position + 4 > m_Size)
      {
        // The file ends inside the meta group, or right after it with nothing to read: GDCM asserts on both.
        Need(8, "the file meta information");
      }
      if (PeekGroup() != 0x0002)
      {
        break;
      }
      uint16_t group, element;
      uint32_t length;
      ReadHeader(true, group, element, length); // the meta group is always explicit VR
      if (length == undefinedLength)
      {
        throw Unknown{};
      }
      if (element == 0x0010)
      {
        syntax = ReadString(length);
      }
      Skip(length, group, element);
    }
    while (!syntax.empty() && (syntax.back() == '\0' || syntax.back() == ' '))
    {
      syntax.pop_back();
    }
    if (syntax.empty())
    {
      throw Truncated{ "the file meta information has no transfer syntax (0002,0010)" };
    }
    return syntax;
  }

  /** Walks the data set to the end of the file. */
  void
  WalkDataSet(bool explicitVR)
  {
    while (m_Position < m_Size)
    {
      WalkElement(0, explicitVR);
    }
  }

private:
  void
  Need(uint64_t bytes, const std::string & what)
  {
    if (m_Position + bytes > m_Size)
    {
      std::ostringstream message;
      message << what << " needs " << bytes << " bytes at offset " << m_Position << ", the file ends at " << m_Size;
      throw Truncated{ message.str() };
    }
  }

  void
  Read(void * destination, uint64_t bytes, const std::string & what)
  {
    Need(bytes, what);
    m_Stream.seekg(static_cast<std::streamoff>(m_Position));
    if (!m_Stream.read(static_cast<char *>(destination), static_cast<std::streamsize>(bytes)))
    {
      throw Truncated{ what + ": read error" };
    }
    m_Position += bytes;
  }

  static uint16_t
  U16(const unsigned char * b)
  {
    return static_cast<uint16_t>(b[0] | (b[1] << 8));
  }

  static uint32_t
  U32(const unsigned char * b)
  {
    return static_cast<uint32_t>(b[0]) | (static_cast<uint32_t>(b[1]) << 8) | (static_cast<uint32_t>(b[2]) << 16) |
           (static_cast<uint32_t>(b[3]) << 24);
  }

  uint16_t
  PeekGroup()
  {
    unsigned char b[2];
    Read(b, 2, "a tag");
    m_Position -= 2;
    return U16(b);
  }

  std::string
  ReadString(uint32_t length)
  {
    if (length > 256)
    {
      throw Unknown{};
    }
    std::string value(length, '\0');
    Read(&value[0], length, "a transfer syntax UID");
    m_Position -= length;
    return value;
  }

  void
  Skip(uint64_t bytes, uint16_t group, uint16_t element)
  {
    Need(bytes, "element " + TagName(group, element));
    m_Position += bytes;
  }

  /** An element header: the tag, then in explicit VR two VR letters and a 16-bit length, or two reserved bytes and
   * a 32-bit length; in implicit VR (and for items and delimiters) a 32-bit length. */
  void
  ReadHeader(bool explicitVR, uint16_t & group, uint16_t & element, uint32_t & length)
  {
    unsigned char b[8];
    Read(b, 8, "an element header");
    group = U16(b);
    element = U16(b + 2);
    m_LastVR = "";
    if (!explicitVR || group == 0xFFFE)
    {
      length = U32(b + 4);
      return;
    }
    const std::string        vr{ static_cast<char>(b[4]), static_cast<char>(b[5]) };
    static const std::string longForm = " OB OD OF OL OV OW SQ SV UC UN UR UT UV ";
    static const std::string shortForm = " AE AS AT CS DA DS DT FD FL IS LO LT PN SH SL SS ST TM UI UL US ";
    if (longForm.find(" " + vr + " ") != std::string::npos)
    {
      unsigned char l[4];
      Read(l, 4, "the length of element " + TagName(group, element));
      length = U32(l);
    }
    else if (shortForm.find(" " + vr + " ") != std::string::npos)
    {
      length = U16(b + 6);
    }
    else
    {
      throw Unknown{};
    }
    m_LastVR = vr;
  }

  /** One element at the current position; sequences and encapsulated pixel data are walked item by item. Returns
   * false on a delimitation item (the end of an undefined-length item or sequence). */
  bool
  WalkElement(unsigned depth, bool explicitVR)
  {
    if (depth > maximumDepth)
    {
      throw Unknown{};
    }
    uint16_t group, element;
    uint32_t length;
    ReadHeader(explicitVR, group, element, length);
    if (group == 0xFFFE)
    {
      if (element == 0xE00D || element == 0xE0DD)
      {
        return false; // a delimiter: its length is 0
      }
      throw Unknown{}; // an item outside a sequence
    }
    if (length != undefinedLength)
    {
      Skip(length, group, element);
      return true;
    }
    // Undefined length: a sequence, encapsulated pixel data, or (UN) a sequence in implicit VR.
    const bool nestedExplicit = explicitVR && m_LastVR != "UN";
    const bool fragments = group == 0x7FE0 && element == 0x0010;
    WalkItems(depth + 1, nestedExplicit, fragments, TagName(group, element));
    return true;
  }

  /** Items up to the sequence delimiter. Defined-length items are skipped; undefined ones walked. */
  void
  WalkItems(unsigned depth, bool explicitVR, bool fragments, const std::string & owner)
  {
    for (;;)
    {
      unsigned char b[8];
      Read(b, 8, "an item of " + owner);
      const uint16_t group = U16(b);
      const uint16_t element = U16(b + 2);
      const uint32_t length = U32(b + 4);
      if (group != 0xFFFE)
      {
        throw Unknown{};
      }
      if (element == 0xE0DD)
      {
        return; // the sequence delimiter
      }
      if (element != 0xE000)
      {
        throw Unknown{};
      }
      if (length != undefinedLength)
      {
        Need(length, (fragments ? "a pixel-data fragment of " : "an item of ") + owner);
        m_Position += length;
      }
      else if (fragments)
      {
        throw Unknown{};
      }
      else
      {
        while (WalkElement(depth, explicitVR))
        {}
      }
    }
  }

  std::ifstream & m_Stream;
  uint64_t        m_Size;
  uint64_t        m_Position{ 0 };
  std::string     m_LastVR; // of the last element header read (empty in implicit VR)
};
} // namespace

bool
IsDicomPart10File(const std::string & path)
{
  std::ifstream stream(path, std::ios::binary);
  char          preamble[132] = {};
  return stream.read(preamble, sizeof(preamble)) && std::string(preamble + 128, 4) == "DICM";
}

std::string
FindDicomTruncation(const std::string & path)
{
  if (!IsDicomPart10File(path))
  {
    return "";
  }
  std::ifstream stream(path, std::ios::binary | std::ios::ate);
  const auto    size = static_cast<uint64_t>(stream.tellg());
  try
  {
    HeaderWalker      walker(stream, size);
    const std::string syntax = walker.WalkMetaGroup();
    if (syntax == "1.2.840.10008.1.2.2" || syntax == "1.2.840.10008.1.2.1.99")
    {
      return ""; // big endian or deflated: GDCM's business
    }
    walker.WalkDataSet(syntax != "1.2.840.10008.1.2");
  }
  catch (const Truncated & truncated)
  {
    return truncated.What;
  }
  catch (const Unknown &)
  {
    return "";
  }
  return "";
}
} // namespace pbdrr
