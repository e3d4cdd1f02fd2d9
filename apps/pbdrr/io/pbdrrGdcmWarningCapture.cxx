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
#include "pbdrrGdcmWarningCapture.h"

#include "gdcmTrace.h"

#include <string>

namespace pbdrr
{
std::string
LockedTextBuffer::Text() const
{
  const std::lock_guard<std::mutex> lock(m_Mutex);
  return m_Text;
}

std::streamsize
LockedTextBuffer::xsputn(const char * text, std::streamsize length)
{
  const std::lock_guard<std::mutex> lock(m_Mutex);
  m_Text.append(text, static_cast<size_t>(length));
  return length;
}

LockedTextBuffer::int_type
LockedTextBuffer::overflow(int_type character)
{
  if (!traits_type::eq_int_type(character, traits_type::eof()))
  {
    const std::lock_guard<std::mutex> lock(m_Mutex);
    m_Text.push_back(traits_type::to_char_type(character));
  }
  return traits_type::not_eof(character);
}

GdcmWarningCapture::GdcmWarningCapture()
  : m_WarningsWereOn(gdcm::Trace::GetWarningFlag())
  , m_WarningStream(gdcm::Trace::GetWarningStream())
  , m_ErrorStream(gdcm::Trace::GetErrorStream())
{
  gdcm::Trace::SetWarningStream(m_Stream);
  gdcm::Trace::SetErrorStream(m_Stream);
  gdcm::Trace::WarningOn();
}

GdcmWarningCapture::~GdcmWarningCapture()
{
  gdcm::Trace::SetWarning(m_WarningsWereOn);
  gdcm::Trace::SetWarningStream(m_WarningStream);
  gdcm::Trace::SetErrorStream(m_ErrorStream);
}

bool
GdcmWarningCapture::PixelDataDamaged() const
{
  const std::string text = m_Buffer.Text();
  return text.find("Incomplete Pixel Data") != std::string::npos ||
         text.find("Fragment could not be read") != std::string::npos ||
         text.find("could be corrupted") != std::string::npos;
}
} // namespace pbdrr
