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
#include "pbdrrDicomContent.h"
#include "pbdrrDicomFileCheck.h"
#include "pbdrrDicomValues.h"
#include "pbdrrLoaderText.h"

#include "gdcmReader.h"

namespace pbdrr
{
DicomContent
ClassifyDicomFile(const std::string & file)
{
  if (!IsDicomPart10File(file))
  {
    return DicomContent::NotDicom;
  }
  GdcmWarningCapture warnings;
  gdcm::Reader       reader;
  reader.SetFileName(file.c_str());
  if (!reader.Read() || warnings.PixelDataDamaged())
  {
    return DicomContent::Damaged;
  }
  const gdcm::DataSet & dataSet = reader.GetFile().GetDataSet();
  // The file meta information names the SOP class of every Part 10 file, a DICOMDIR's too (its data set has none).
  std::string storageClass;
  StringValue(reader.GetFile().GetHeader(), gdcm::Tag(0x0002, 0x0002), storageClass);
  if (storageClass == MediaStorageDirectorySOPClass)
  {
    return DicomContent::Directory;
  }
  if (dataSet.FindDataElement(gdcm::Tag(0x7fe0, 0x0010)))
  {
    return DicomContent::Image;
  }
  // No pixel data. Every DICOM object names its SOP class; a CT image without pixels is a file cut short at an
  // element boundary (its header walks clean), not a report.
  std::string sopClass, modality;
  if (!StringValue(dataSet, gdcm::Tag(0x0008, 0x0016), sopClass))
  {
    return DicomContent::Damaged;
  }
  StringValue(dataSet, gdcm::Tag(0x0008, 0x0060), modality);
  const bool ctImage = sopClass.rfind("1.2.840.10008.5.1.4.1.1.2", 0) == 0 || modality.rfind("CT", 0) == 0 ||
                       dataSet.FindDataElement(gdcm::Tag(0x0028, 0x0010));
  return ctImage ? DicomContent::Damaged : DicomContent::NoImage;
}

void
RefuseDamagedPixelData(const GdcmWarningCapture & warnings, const std::vector<std::string> & files)
{
  if (!warnings.PixelDataDamaged())
  {
    return;
  }
  std::vector<std::string> damaged;
  for (const auto & file : files)
  {
    if (ClassifyDicomFile(file) == DicomContent::Damaged)
    {
      damaged.push_back(file);
    }
  }
  Fail("the pixel data of " + (damaged.empty() ? std::string("the DICOM files") : JoinNames(damaged)) +
       " is incomplete or damaged; pbdrr does not render it rather than render it wrong");
}
} // namespace pbdrr
