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
#include "pbdrrBatch.h"

#include <chrono>
#include <cstdio>
#include <unistd.h>

namespace pbdrr
{
double
SteadySeconds()
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

BatchProgress::BatchProgress(uint64_t total, bool enabled)
  : m_Total(total)
  , m_Enabled(enabled)
  , m_Terminal(isatty(fileno(stderr)) != 0)
  , m_Start(SteadySeconds())
  , m_LastPrint(m_Start)
{}

BatchProgress::~BatchProgress()
{
  if (m_Enabled && m_Terminal && !m_Finished && m_Done > 0)
  {
    std::fprintf(stderr, "\n");
  }
}

void
BatchProgress::ViewDone()
{
  ++m_Done;
  const double now = SteadySeconds();
  if (m_Enabled && (m_Terminal ? now - m_LastPrint >= 0.2 : now - m_LastPrint >= 10.0))
  {
    m_LastPrint = now;
    this->Print(false);
  }
}

void
BatchProgress::Print(bool final)
{
  const double seconds = SteadySeconds() - m_Start;
  const double rate = seconds > 0.0 ? static_cast<double>(m_Done) / seconds : 0.0;
  char         line[160];
  if (final)
  {
    std::snprintf(line,
                  sizeof(line),
                  "pbdrr: rendered %llu views in %.1f s (%.1f views/s)",
                  static_cast<unsigned long long>(m_Done),
                  seconds,
                  rate);
  }
  else
  {
    const double left = rate > 0.0 ? static_cast<double>(m_Total - m_Done) / rate : 0.0;
    std::snprintf(line,
                  sizeof(line),
                  "pbdrr: views %llu / %llu, %.1f views/s, about %.0f s left",
                  static_cast<unsigned long long>(m_Done),
                  static_cast<unsigned long long>(m_Total),
                  rate,
                  left);
  }
  if (m_Terminal)
  {
    std::fprintf(stderr, "\r%-79s%s", line, final ? "\n" : "");
  }
  else
  {
    std::fprintf(stderr, "%s\n", line);
  }
  std::fflush(stderr);
}

void
BatchProgress::Finish()
{
  if (m_Enabled && !m_Finished)
  {
    this->Print(true);
  }
  m_Finished = true;
}
} // namespace pbdrr
