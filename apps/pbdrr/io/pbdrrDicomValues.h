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
#ifndef pbdrrDicomValues_h
#define pbdrrDicomValues_h

#include "gdcmDataSet.h"
#include "gdcmSequenceOfItems.h"
#include "gdcmTag.h"

#include <string>
#include <vector>

namespace pbdrr
{
/** Parses a multi-valued DICOM number string ("0.9\0.9") into `numbers`; true if it holds exactly `count` numbers
 * (false for a missing value, nullptr). */
bool
ParseNumbers(const char * text, size_t count, std::vector<double> & numbers);

/** The value of `tag` in a data set as stored (padding included); false if absent or without a value. */
bool
StringValue(const gdcm::DataSet & dataSet, const gdcm::Tag & tag, std::string & value);

/** The items of sequence `tag` in a data set (empty if absent). The items live in the sequences `keep` holds. */
std::vector<const gdcm::DataSet *>
SequenceItems(const gdcm::DataSet &                                    dataSet,
              const gdcm::Tag &                                        tag,
              std::vector<gdcm::SmartPointer<gdcm::SequenceOfItems>> & keep);

/** Value `tag` of the functional group `groupTag` (e.g. Plane Position Sequence) of one functional-groups item. */
bool
FunctionalGroupValue(const gdcm::DataSet & groups,
                     const gdcm::Tag &     groupTag,
                     const gdcm::Tag &     tag,
                     std::string &         value);
} // namespace pbdrr

#endif
