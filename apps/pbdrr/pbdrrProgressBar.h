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
#ifndef pbdrrProgressBar_h
#define pbdrrProgressBar_h

#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <unistd.h>

namespace pbdrr
{
/** Progress on a terminal only (never into a file or a pipe), shown once the work has run for half a second: a bar
 * with the time left for a render, a count of files for a load. */
class ProgressBar
{
public:
  explicit ProgressBar(bool enabled)
    : m_Enabled(enabled && isatty(fileno(stderr))), m_Start(std::chrono::steady_clock::now())
  {}
  ~ProgressBar() { this->Finish(); }

  /** The bar at progress (0 to 1), with what is being done (e.g. " slab 3 of 32") after the time left. */
  void
  Show(float progress, const std::string & what = std::string())
  {
    if (!this->Due())
    {
      return;
    }
    if (progress + 0.01f < m_LastProgress)
    {
      m_PhaseStart = std::chrono::steady_clock::now(); // a new stage of the render (the control variate's coarse image,
                                                       // then the points)
    }
    m_LastProgress = progress;
    const int width = 40;
    const int filled = static_cast<int>(progress * width + 0.5f);
    std::fprintf(stderr,
                 "\r[%s%s] %3d%%%s%s",
                 std::string(filled, '=').c_str(),
                 std::string(width - filled, ' ').c_str(),
                 static_cast<int>(progress * 100.0f + 0.5f),
                 TimeLeft(progress, SecondsSinceStart(m_PhaseStart)).c_str(),
                 what.c_str());
    std::fflush(stderr);
    m_Shown = true;
  }

  /** "what done / total", e.g. the files of a DICOM series read so far. */
  void
  ShowCount(const char * what, size_t done, size_t total)
  {
    if (!this->Due())
    {
      return;
    }
    std::fprintf(stderr, "\r%s %zu / %zu", what, done, total);
    std::fflush(stderr);
    m_Shown = true;
  }

  void
  Finish()
  {
    if (m_Shown)
    {
      std::fprintf(stderr, "\r%80s\r", "");
      std::fflush(stderr);
      m_Shown = false;
    }
  }

private:
  static double
  SecondsSinceStart(std::chrono::steady_clock::time_point start)
  {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  /** On a terminal, once the work has run for half a second. */
  bool
  Due() const
  {
    return m_Enabled && SecondsSinceStart(m_Start) >= 0.5;
  }

  /** ", about 12 s left": the elapsed time scaled by what is left, once 2% is done (blank before, and at the end). */
  static std::string
  TimeLeft(float progress, double elapsedSeconds)
  {
    if (!(progress >= 0.02f) || progress >= 1.0f)
    {
      return "                    ";
    }
    const auto left = static_cast<long>(std::lround(elapsedSeconds * (1.0 - progress) / progress));
    char       text[64];
    if (left < 1)
    {
      std::snprintf(text, sizeof(text), ", under a second left  ");
    }
    else if (left < 60)
    {
      std::snprintf(text, sizeof(text), ", about %ld s left     ", left);
    }
    else
    {
      std::snprintf(text, sizeof(text), ", about %ld min %02ld s left", left / 60, left % 60);
    }
    return text;
  }

  bool                                  m_Enabled;
  bool                                  m_Shown{ false };
  std::chrono::steady_clock::time_point m_Start;
  std::chrono::steady_clock::time_point m_PhaseStart{ m_Start };
  float                                 m_LastProgress{ 0.0f };
};
} // namespace pbdrr

#endif
