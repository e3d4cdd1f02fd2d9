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
#include "pbdrrVolumeFileReader.h"
#include "pbdrrLoaderText.h"

#include "itkDRRImageFileIntegrity.h"
#include "itkImageFileReader.h"

#include <iostream>
#include <sstream>

namespace pbdrr
{
namespace
{
template <typename TVolume>
typename TVolume::Pointer
ReadVolumeFileAs(const std::string & path, const itk::ImageIOBase::Pointer & io)
{
  if (io->GetNumberOfDimensions() != 3)
  {
    Fail(path + " is a " + std::to_string(io->GetNumberOfDimensions()) +
         "D image; pbdrr needs a 3D volume (a CT series or volume file)");
  }
  if (io->GetNumberOfComponents() != 1)
  {
    Fail(path + " has " + std::to_string(io->GetNumberOfComponents()) +
         " components per voxel; pbdrr needs scalar voxels (HU or mu)");
  }
  auto reader = itk::ImageFileReader<TVolume>::New();
  reader->SetFileName(path);
  reader->SetImageIO(io);
  // Some readers (MetaImage) report a short read on std::cerr and carry on: listen, and refuse such a volume.
  std::ostringstream readerMessages;
  std::streambuf *   standardError = std::cerr.rdbuf(readerMessages.rdbuf());
  try
  {
    reader->Update();
  }
  catch (...)
  {
    std::cerr.rdbuf(standardError);
    throw;
  }
  std::cerr.rdbuf(standardError);
  const std::string messages = readerMessages.str();
  if (messages.find("not read completely") != std::string::npos || messages.find("rror") != std::string::npos)
  {
    Fail("cannot read " + path + ": the file is truncated or damaged (" + messages.substr(0, messages.find('\n')) +
         ")");
  }
  std::cerr << messages;
  typename TVolume::Pointer image = reader->GetOutput();
  image->DisconnectPipeline(); // the volume is data from now on: no reader re-executes behind it
  return image;
}
} // namespace

void
RefuseDamagedImageFile(const std::string & path)
{
  const std::string damage = itk::DRRImageFileIntegrity::FindDamage(path);
  if (!damage.empty())
  {
    Fail("cannot read " + path + ": " + damage);
  }
}

VolumeType::Pointer
ReadVolumeFile(const std::string & path, const itk::ImageIOBase::Pointer & io)
{
  return ReadVolumeFileAs<VolumeType>(path, io);
}

void
ReadVolumeFileInto(const std::string & path, const itk::ImageIOBase::Pointer & io, LoadedVolume & loaded)
{
  using ComponentEnum = itk::IOComponentEnum;
  const ComponentEnum component = io->GetComponentType();
  if (component == ComponentEnum::CHAR || component == ComponentEnum::UCHAR || component == ComponentEnum::SHORT)
  {
    loaded.Set(ReadVolumeFileAs<HUVolumeType>(path, io));
    return;
  }
  loaded.Set(ReadVolumeFileAs<VolumeType>(path, io));
}
} // namespace pbdrr
