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
#ifndef pbdrrOutputFiles_h
#define pbdrrOutputFiles_h

#include <cstdint>
#include <functional>
#include <string>

namespace pbdrr
{
/** The output name of a batch's views: a path with one printf counter (%d, %4d or %04d: view_%04d.mha), which view k
 * replaces with k; %% is a literal %. */
class OutputPattern
{
public:
  /** Parses pattern; throws UsageError for a % that is not a counter or %%, or for more than one counter. */
  explicit OutputPattern(std::string pattern);

  /** True if the pattern holds a counter. */
  bool
  HasCounter() const
  {
    return m_Counter != std::string::npos;
  }

  /** The path of view k (the pattern itself, %% made %, if it holds no counter). */
  std::string
  Format(uint64_t k) const;

  /** The pattern as given. */
  const std::string &
  GetPattern() const
  {
    return m_Pattern;
  }

private:
  std::string m_Pattern;
  size_t      m_Counter{ std::string::npos }; // where the counter starts
  size_t      m_CounterLength{ 0 };
  unsigned    m_Width{ 0 };
  bool        m_ZeroPadded{ false };
};

/** The folder of path ("." for a bare name). */
std::string
DirectoryOf(const std::string & path);

/** A name beside path for a file being written: the same folder (so that a rename is atomic), hidden, unique to the
 * process, and the same extension (so that ITK picks the same writer): dir/.name.partial-PID.ext. */
std::string
TemporaryPathBeside(const std::string & path);

/** Writes the file at path through write(temporary) and renames it to path, so that path is either absent or whole:
 * a run killed midway leaves no half-written file under the name (only, at worst, a hidden .partial one). Before the
 * rename, an image must hold what its header promises (CheckWrittenImage()) and the file is flushed to the disk
 * (fsync); after it, the folder. If any of these fails, or write throws, the temporary file is removed and the
 * exception passed on (a short write says so: a full disk, a file size limit). */
void
WriteAtomically(const std::string & path, const std::function<void(const std::string & temporaryPath)> & write);

/** Throws std::runtime_error naming path if the image file `written` (path itself, or its temporary name) holds less
 * than its header promises (itk::DRRImageFileIntegrity; nothing is checked for formats it does not know). */
void
CheckWrittenImage(const std::string & written, const std::string & path);

/** Removes, in folder, the temporary files of WriteAtomically() (.NAME.partial-PID.EXT) whose process PID is gone: a
 * run killed between a write and its rename leaves one. Those of a running process (another shard) stay. */
void
RemoveStalePartialFiles(const std::string & folder);

/** True if the image file at path is whole: what its header promises is there (itk::DRRImageFileIntegrity), and ITK
 * reads its header and every pixel. What --resume asks of a view it skips. */
bool
IsWholeImageFile(const std::string & path);

/** True for formats whose pixels are in a second file (.mhd, .nhdr): they cannot be renamed as one. */
bool
HasDetachedHeader(const std::string & path);

/** True if a folder exists at path. */
bool
IsDirectoryPath(const std::string & path);

/** True if a file exists at path. */
bool
FileExists(const std::string & path);
} // namespace pbdrr

#endif
