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
#ifndef pbdrrGdcmWarningCapture_h
#define pbdrrGdcmWarningCapture_h

#include <mutex>
#include <ostream>
#include <streambuf>
#include <string>

namespace pbdrr
{
/** A text that several threads may write to at once (GDCM reading files in parallel writes its warnings to one
 * global stream): every character reaches it through a lock, as the buffer keeps none of its own. The stream over it
 * is shared state that GDCM's messages only read, or set to the width 0 it already has, as with std::cerr. */
class LockedTextBuffer : public std::streambuf
{
public:
  std::string
  Text() const;

protected:
  std::streamsize
  xsputn(const char * text, std::streamsize length) override;
  int_type
  overflow(int_type character) override;

private:
  mutable std::mutex m_Mutex;
  std::string        m_Text;
};

/** Listens to GDCM while it reads: it reports pixel data cut short (and then fills the gap) only as a warning; its
 * errors are kept out of the user's way too (pbdrr says what went wrong in its own words). Captures nest: each one
 * restores, when it ends, the streams and the warning flag it found. GDCM may write to a capture from several threads
 * at once. */
class GdcmWarningCapture
{
public:
  GdcmWarningCapture();
  ~GdcmWarningCapture();
  GdcmWarningCapture(const GdcmWarningCapture &) = delete;
  GdcmWarningCapture &
  operator=(const GdcmWarningCapture &) = delete;

  /** GDCM found the pixel data incomplete (a truncated file) or a compressed fragment unreadable. */
  bool
  PixelDataDamaged() const;

private:
  LockedTextBuffer m_Buffer;
  std::ostream     m_Stream{ &m_Buffer };
  bool             m_WarningsWereOn;
  std::ostream &   m_WarningStream;
  std::ostream &   m_ErrorStream;
};
} // namespace pbdrr

#endif
