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

#include "itkDRRImageFileIntegrity.h"
#include "itkImageIOFactory.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <signal.h>
#include <stdexcept>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

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
CheckWrittenImage(const std::string & written, const std::string & path)
{
  if (!itk::DRRImageFileIntegrity::IsCheckedFormat(written))
  {
    // PNG and the others: an image ITK reads must read back whole (libpng's reader throws on a cut stream).
    const bool image =
      itk::ImageIOFactory::CreateImageIO(written.c_str(), itk::ImageIOFactory::IOFileModeEnum::ReadMode).IsNotNull();
    if (image && !IsWholeImageFile(written))
    {
      throw std::runtime_error("cannot write " + path +
                               ": it does not read back whole (is the disk full, or a file size limit reached?)");
    }
    return;
  }
  std::string damage = itk::DRRImageFileIntegrity::FindDamage(written);
  if (!damage.empty())
  {
    const std::string truncated = ": the file is truncated";
    if (damage.size() > truncated.size() &&
        damage.compare(damage.size() - truncated.size(), truncated.size(), truncated) == 0)
    {
      damage.resize(damage.size() - truncated.size());
    }
    throw std::runtime_error("cannot write " + path + ": it was written short, " + damage +
                             " (is the disk full, or a file size limit reached?)");
  }
}

namespace
{
/** fsync of the file at path; throws naming `named` if it fails. */
void
SyncToDisk(const std::string & path, const std::string & named)
{
  const int descriptor = open(path.c_str(), O_RDONLY);
  if (descriptor < 0 || fsync(descriptor) != 0)
  {
    const std::string reason = std::strerror(errno);
    if (descriptor >= 0)
    {
      close(descriptor);
    }
    throw std::runtime_error("cannot write " + named + ": " + reason);
  }
  if (close(descriptor) != 0)
  {
    throw std::runtime_error("cannot write " + named + ": " + std::strerror(errno));
  }
}
} // namespace

void
WriteAtomically(const std::string & path, const std::function<void(const std::string & temporaryPath)> & write)
{
  const std::string temporary = TemporaryPathBeside(path);
  try
  {
    write(temporary);
    // Writers do not all see a short write (ITK's MetaImage writer does not check its stream): the file must hold
    // what its header promises, and be on the disk, before it takes the name.
    CheckWrittenImage(temporary, path);
    SyncToDisk(temporary, path);
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
  // The rename itself on the disk: a crash after it does not bring the old name back.
  const int folder = open(DirectoryOf(path).c_str(), O_RDONLY | O_DIRECTORY);
  if (folder >= 0)
  {
    fsync(folder); // best effort: some file systems refuse a folder's fsync, and the data are already on the disk
    close(folder);
  }
}

void
RemoveStalePartialFiles(const std::string & folder)
{
  std::error_code error;
  for (const auto & entry : std::filesystem::directory_iterator(folder, error))
  {
    const std::string name = entry.path().filename().string();
    const size_t      mark = name.find(".partial-");
    if (name.empty() || name[0] != '.' || mark == std::string::npos)
    {
      continue;
    }
    const std::string digits = name.substr(mark + 9, name.find('.', mark + 9) - mark - 9);
    if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos)
    {
      continue;
    }
    const pid_t writer = static_cast<pid_t>(std::stoll(digits));
    if (writer != getpid() && kill(writer, 0) != 0 && errno == ESRCH)
    {
      std::filesystem::remove(entry.path(), error);
    }
  }
}

bool
IsWholeImageFile(const std::string & path)
{
  if (!FileExists(path) || !itk::DRRImageFileIntegrity::FindDamage(path).empty())
  {
    return false;
  }
  // Its header readable and every pixel read (PNG's reader, unchecked above, throws on a cut stream).
  try
  {
    const itk::ImageIOBase::Pointer io =
      itk::ImageIOFactory::CreateImageIO(path.c_str(), itk::ImageIOFactory::IOFileModeEnum::ReadMode);
    if (!io)
    {
      return false;
    }
    io->SetFileName(path);
    io->ReadImageInformation();
    std::vector<char>  pixels(static_cast<size_t>(io->GetImageSizeInBytes()));
    itk::ImageIORegion region(io->GetNumberOfDimensions());
    for (unsigned d = 0; d < io->GetNumberOfDimensions(); ++d)
    {
      region.SetSize(d, io->GetDimensions(d));
    }
    io->SetIORegion(region);
    io->Read(pixels.data());
  }
  catch (const itk::ExceptionObject &)
  {
    return false;
  }
  return true;
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
