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
#include "pbdrrMessages.h"

#include <algorithm>

#include "itkObjectFactory.h"
#include "itkOutputWindow.h"

#include <cmath>
#include <iostream>
#include <regex>
#include <sstream>

namespace pbdrr
{
std::string
FormatNumber(double value)
{
  std::ostringstream text;
  text << value;
  return text.str();
}

double
RoundedForDisplay(double value)
{
  if (!std::isfinite(value) || std::abs(value) >= 1e6)
  {
    return value; // nothing to tidy beyond the 6 digits printed; and 1e9 x value must not overflow
  }
  const double rounded = std::round(value * 1e9) / 1e9;
  return rounded == 0.0 ? 0.0 : rounded; // -0 == 0: the positive zero
}

namespace
{
bool quietMessages = false;

/** ITK's output window for pbdrr: one clean line per warning; errors are reported by the caller. */
class MessageWindow : public itk::OutputWindow
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(MessageWindow);
  using Self = MessageWindow;
  using Pointer = itk::SmartPointer<Self>;
  itkNewMacro(Self);

  void
  DisplayText(const char * text) override
  {
    const std::string message = CleanMessage(text);
    // GDCM's series helper warns before pbdrr's own, clearer, error about the same directory.
    if (quietMessages || message.empty() || message.find("No Series were found") != std::string::npos)
    {
      return;
    }
    std::cerr << "pbdrr: warning: " << message << std::endl;
  }

protected:
  MessageWindow() = default;
};
} // namespace

std::string
CleanMessage(const std::string & message)
{
  static const std::regex machinery(
    R"((ITK ERROR: |WARNING: )|(In [^\n]*, line [0-9]+\n)|([A-Za-z_][A-Za-z0-9_:<>, ]* ?\(0x[0-9a-fA-F]+\): ))");
  std::string clean = std::regex_replace(message, machinery, "");
  while (!clean.empty() && (clean.back() == '\n' || clean.back() == ' '))
  {
    clean.pop_back();
  }
  return clean;
}

void
InstallMessageWindow()
{
  itk::OutputWindow::SetInstance(MessageWindow::New());
}

void
SetQuietMessages(bool quiet)
{
  quietMessages = quiet;
}
std::string
Lowercase(std::string s)
{
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

bool
EndsWith(const std::string & s, const std::string & suffix)
{
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::string
JoinWords(const std::vector<std::string> & words, const std::string & separator)
{
  std::string text;
  for (const auto & word : words)
  {
    text += (text.empty() ? "" : separator) + word;
  }
  return text;
}
} // namespace pbdrr
