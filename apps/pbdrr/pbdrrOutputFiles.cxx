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
#include "pbdrrOutputFiles.h"
#include "pbdrrMessages.h"
#include "pbdrrOptions.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <sys/stat.h>
#include <unistd.h>

namespace pbdrr
{
OutputPattern::OutputPattern(std::string pattern) : m_Pattern(std::move(pattern))
{
  for (size_t i = 0; i < m_Pattern.size(); ++i)
  {
    if (m_Pattern[i] != '%')
    {
      continue;
    }
    if (i + 1 < m_Pattern.size() && m_Pattern[i + 1] == '%')
    {
      ++i;
      continue;
    }
    size_t       end = i + 1;
    const bool   zero = end < m_Pattern.size() && m_Pattern[end] == '0';
    const size_t digits = end;
    while (end < m_Pattern.size() && m_Pattern[end] >= '0' && m_Pattern[end] <= '9')
    {
      ++end;
    }
    if (end >= m_Pattern.size() || m_Pattern[end] != 'd' || end - digits > 2)
    {
      throw UsageError("output " + m_Pattern + ": a % must be a view counter (%d, %4d, %04d) or %%");
    }
    if (this->HasCounter())
    {
      throw UsageError("output " + m_Pattern + ": more than one view counter (give one, e.g. view_%04d.mha)");
    }
    m_Counter = i;
    m_CounterLength = end + 1 - i;
    m_ZeroPadded = zero;
    m_Width = end > digits ? static_cast<unsigned>(std::stoul(m_Pattern.substr(digits, end - digits))) : 0;
    i = end;
  }
}

std::string
OutputPattern::Format(uint64_t k) const
{
  std::string path;
  for (size_t i = 0; i < m_Pattern.size(); ++i)
  {
    if (i == m_Counter)
    {
      std::string number = std::to_string(k);
      if (number.size() < m_Width)
      {
        number.insert(0, m_Width - number.size(), m_ZeroPadded ? '0' : ' ');
      }
      path += number;
      i += m_CounterLength - 1;
    }
    else
    {
      path += m_Pattern[i];
      i += m_Pattern[i] == '%' ? 1 : 0; // %% (the constructor refused any other % outside the counter)
    }
  }
  return path;
}

std::string
DirectoryOf(const std::string & path)
{
  const size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? "." : (slash == 0 ? "/" : path.substr(0, slash));
}

namespace
{
/** The extension ITK chooses the writer by: ".nii.gz" or from the last dot of the file name ("" if none). */
std::string
ExtensionOf(const std::string & name)
{
  if (EndsWith(Lowercase(name), ".nii.gz"))
  {
    return name.substr(name.size() - 7);
  }
  const size_t dot = name.find_last_of('.');
  return dot == std::string::npos || dot == 0 ? std::string() : name.substr(dot);
}
} // namespace

std::string
TemporaryPathBeside(const std::string & path)
{
  const size_t      slash = path.find_last_of('/');
  const std::string folder = slash == std::string::npos ? "" : path.substr(0, slash + 1);
  const std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
  const std::string extension = ExtensionOf(name);
  return folder + "." + name.substr(0, name.size() - extension.size()) + ".partial-" + std::to_string(getpid()) +
         extension;
}

void
WriteAtomically(const std::string & path, const std::function<void(const std::string & temporaryPath)> & write)
{
  const std::string temporary = TemporaryPathBeside(path);
  try
  {
    write(temporary);
  }
  catch (...)
  {
    std::remove(temporary.c_str());
    throw;
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0)
  {
    const std::string reason = std::strerror(errno);
    std::remove(temporary.c_str());
    throw std::runtime_error("cannot write " + path + ": " + reason);
  }
}

bool
HasDetachedHeader(const std::string & path)
{
  const std::string lower = Lowercase(path);
  return EndsWith(lower, ".mhd") || EndsWith(lower, ".nhdr");
}

bool
FileExists(const std::string & path)
{
  struct stat status;
  return stat(path.c_str(), &status) == 0 && S_ISREG(status.st_mode);
}
} // namespace pbdrr

namespace pbdrr
{
bool
IsDirectoryPath(const std::string & path)
{
  struct stat status;
  return stat(path.c_str(), &status) == 0 && S_ISDIR(status.st_mode);
}
} // namespace pbdrr
