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
#include "pbdrrDicomValues.h"

#include <algorithm>
#include <sstream>

namespace pbdrr
{
bool
ParseNumbers(const char * text, size_t count, std::vector<double> & numbers)
{
  numbers.clear();
  if (text == nullptr)
  {
    return false;
  }
  std::string s(text);
  std::replace(s.begin(), s.end(), '\\', ' ');
  std::istringstream stream(s);
  for (double v; stream >> v;)
  {
    numbers.push_back(v);
  }
  return numbers.size() == count;
}

bool
StringValue(const gdcm::DataSet & dataSet, const gdcm::Tag & tag, std::string & value)
{
  if (!dataSet.FindDataElement(tag))
  {
    return false;
  }
  const gdcm::ByteValue * bytes = dataSet.GetDataElement(tag).GetByteValue();
  if (!bytes)
  {
    return false;
  }
  value.assign(bytes->GetPointer(), bytes->GetLength());
  return true;
}

std::vector<const gdcm::DataSet *>
SequenceItems(const gdcm::DataSet &                                    dataSet,
              const gdcm::Tag &                                        tag,
              std::vector<gdcm::SmartPointer<gdcm::SequenceOfItems>> & keep)
{
  std::vector<const gdcm::DataSet *> items;
  if (!dataSet.FindDataElement(tag))
  {
    return items;
  }
  gdcm::SmartPointer<gdcm::SequenceOfItems> sequence = dataSet.GetDataElement(tag).GetValueAsSQ();
  if (!sequence)
  {
    return items;
  }
  keep.push_back(sequence);
  for (gdcm::SequenceOfItems::SizeType i = 1; i <= sequence->GetNumberOfItems(); ++i)
  {
    items.push_back(&sequence->GetItem(i).GetNestedDataSet());
  }
  return items;
}

bool
FunctionalGroupValue(const gdcm::DataSet & groups,
                     const gdcm::Tag &     groupTag,
                     const gdcm::Tag &     tag,
                     std::string &         value)
{
  std::vector<gdcm::SmartPointer<gdcm::SequenceOfItems>> keep;
  const auto                                             items = SequenceItems(groups, groupTag, keep);
  return !items.empty() && StringValue(*items.front(), tag, value);
}
} // namespace pbdrr
