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
#include "itkDRRImageFileIntegrity.h"
#include "itkDRRImageFileChecks.h"

#include "itkMacro.h"
#include "itkProcessObject.h"
#include "itkSimpleDataObjectDecorator.h"

namespace itk
{
namespace
{
using namespace DRRImageFileChecks;

enum class Format
{
  None,
  MetaImage,
  Nrrd,
  Nifti,
  Tiff
};

Format
FormatOf(const std::string & path)
{
  const std::string lower = Lowercase(path);
  if (EndsWith(lower, ".mha") || EndsWith(lower, ".mhd"))
  {
    return Format::MetaImage;
  }
  if (EndsWith(lower, ".nrrd") || EndsWith(lower, ".nhdr"))
  {
    return Format::Nrrd;
  }
  if (EndsWith(lower, ".nii") || EndsWith(lower, ".nii.gz") || EndsWith(lower, ".hdr") || EndsWith(lower, ".hdr.gz"))
  {
    return Format::Nifti;
  }
  if (EndsWith(lower, ".tif") || EndsWith(lower, ".tiff"))
  {
    return Format::Tiff;
  }
  return Format::None;
}
} // namespace

std::string
DRRImageFileIntegrity::GetSourceFileName(const DataObject * data)
{
  ProcessObject * source = data ? data->GetSource().GetPointer() : nullptr;
  if (!source || !source->HasInput("FileName"))
  {
    return std::string();
  }
  // The named inputs, in the order of their names (ProcessObject::GetInputs()).
  const auto names = source->GetInputNames();
  const auto inputs = source->GetInputs();
  for (size_t k = 0; k < names.size() && k < inputs.size(); ++k)
  {
    const auto * name = dynamic_cast<const SimpleDataObjectDecorator<std::string> *>(inputs[k].GetPointer());
    if (names[k] == "FileName" && name)
    {
      return name->Get();
    }
  }
  return std::string();
}

bool
DRRImageFileIntegrity::IsCheckedFormat(const std::string & path)
{
  return FormatOf(path) != Format::None;
}

std::string
DRRImageFileIntegrity::FindDamage(const std::string & path)
{
  const Format format = FormatOf(path);
  if (format == Format::None)
  {
    return std::string();
  }
  CheckedFile file(path);
  if (!file.GetError().empty())
  {
    return "cannot open it: " + file.GetError();
  }
  switch (format)
  {
    case Format::MetaImage:
      return FindMetaImageDamage(path, file);
    case Format::Nrrd:
      return FindNrrdDamage(path, file);
    case Format::Nifti:
      return FindNiftiDamage(path, file);
    case Format::Tiff:
      return FindTiffDamage(file);
    case Format::None:
      break;
  }
  return std::string();
}

void
DRRImageFileIntegrity::Check(const std::string & path)
{
  const std::string damage = FindDamage(path);
  if (!damage.empty())
  {
    itkGenericExceptionMacro(<< "cannot read " << path << ": " << damage);
  }
}
} // namespace itk
