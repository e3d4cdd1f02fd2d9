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
// What pbdrrIO decides about a DICOM series without reading a file: whether its slices form one regular grid
// (CheckSliceStack) and which series of a directory it reads (SelectDicomSeries). Both take plain lists, as a DICOMDIR
// reader would give them.
#include "pbdrrDicomSeriesDiscovery.h"
#include "pbdrrDicomSliceStack.h"

#include "gtest/gtest.h"

#include <stdexcept>
#include <string>
#include <vector>

namespace
{
const std::vector<double> axial{ 1, 0, 0, 0, 1, 0 };

/** Slices of 4 x 4 pixels, axial unless told, at the given positions along z. */
std::vector<pbdrr::Slice>
Stack(const std::vector<double> & z)
{
  std::vector<pbdrr::Slice> slices;
  for (size_t i = 0; i < z.size(); ++i)
  {
    slices.push_back({ "IM" + std::to_string(i + 1), { 0.0, 0.0, z[i] }, axial, "4 x 4" });
  }
  return slices;
}

/** The message CheckSliceStack refuses the slices with, or "" if it accepts them. */
std::string
Refusal(const std::vector<pbdrr::Slice> & slices)
{
  try
  {
    pbdrr::CheckSliceStack(slices, "the series");
  }
  catch (const std::runtime_error & e)
  {
    return e.what();
  }
  return "";
}

pbdrr::DicomSeriesList
TwoSeries()
{
  pbdrr::DicomSeriesList list;
  list.Series = { { "2.25.1", { "a1", "a2", "a3" } }, { "2.25.2", { "b1", "b2", "b3", "b4", "b5" } } };
  return list;
}
} // namespace

TEST(PbdrrDicomSliceStack, RegularStackGivesItsSpacingAndDirection)
{
  const auto up = pbdrr::CheckSliceStack(Stack({ -10, -7.5, -5, -2.5 }), "the series");
  EXPECT_DOUBLE_EQ(up.Spacing, 2.5);
  EXPECT_TRUE(up.Increasing);
  EXPECT_TRUE(up.Ordered);
  EXPECT_EQ(up.Normal, (pbdrr::Vector3{ 0.0, 0.0, 1.0 }));

  const auto down = pbdrr::CheckSliceStack(Stack({ 5, 3, 1 }), "the series");
  EXPECT_DOUBLE_EQ(down.Spacing, 2.0);
  EXPECT_FALSE(down.Increasing);
  EXPECT_TRUE(down.Ordered);

  const auto shuffled = pbdrr::CheckSliceStack(Stack({ 0, 2, 1, 3 }), "the series");
  EXPECT_DOUBLE_EQ(shuffled.Spacing, 1.0);
  EXPECT_FALSE(shuffled.Ordered);

  const auto one = pbdrr::CheckSliceStack(Stack({ 7 }), "the series");
  EXPECT_DOUBLE_EQ(one.Spacing, 1.0) << "one slice: the default stack";
  EXPECT_TRUE(one.Ordered);
}

TEST(PbdrrDicomSliceStack, MissingAndUnevenSlicesAreRefusedWithTheNumbers)
{
  EXPECT_EQ(Refusal(Stack({ 0, 2.5, 5, 10, 12.5 })),
            "missing slice(s) in the series: slices 2 and 3 (at 5 mm and 10 mm along the normal) are 5 mm apart, the "
            "spacing is 2.5 mm (1 slice(s) missing); pbdrr does not render it rather than render it wrong");
  EXPECT_EQ(Refusal(Stack({ 0, 2.5, 5.6, 8.1, 10.6 })),
            "uneven slice spacing in the series: slices 1 and 2 (at 2.5 mm and 5.6 mm along the normal) are 3.1 mm "
            "apart, the spacing is 2.5 mm; pbdrr does not render it rather than render it wrong");
  EXPECT_EQ(Refusal(Stack({ 0, 2.5, 5.02, 7.5 })), "") << "within 1% of the spacing";
}

TEST(PbdrrDicomSliceStack, DuplicatesTiltAndMixedSlicesAreRefused)
{
  EXPECT_NE(Refusal(Stack({ 0, 2.5, 2.5, 5 })).find("two slices of the series lie at the same position (2.5 mm"),
            std::string::npos);

  auto tilted = Stack({ 0, 2.5, 5 });
  for (size_t i = 0; i < tilted.size(); ++i)
  {
    tilted[i].Position[1] = 0.5 * static_cast<double>(i);
  }
  EXPECT_NE(Refusal(tilted).find("each slice is shifted 0.5 mm sideways per 2.5 mm step"), std::string::npos);

  auto turned = Stack({ 0, 2.5, 5 });
  turned[2].Orientation = { 0, 1, 0, 1, 0, 0 };
  EXPECT_EQ(Refusal(turned), "the slices of the series have different orientations (IM3): not one volume");

  auto resized = Stack({ 0, 2.5, 5 });
  resized[1].Size = "4 x 5";
  EXPECT_EQ(Refusal(resized), "the slices of the series have different sizes (IM2): not one volume");
}

TEST(PbdrrDicomSeriesSelection, WithoutAUIDTheLargestIsReadWithANote)
{
  std::vector<std::string> notes;
  const auto &             chosen = pbdrr::SelectDicomSeries(TwoSeries(), "", "DIR", notes);
  EXPECT_EQ(chosen.UID, "2.25.2");
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_EQ(notes[0],
            "DIR holds 2 DICOM series; using the largest, 2.25.2 (5 files); choose another with --series UID");

  pbdrr::DicomSeriesList tie = TwoSeries();
  tie.Series[1].Files.resize(3);
  notes.clear();
  EXPECT_EQ(pbdrr::SelectDicomSeries(tie, "", "DIR", notes).UID, "2.25.1") << "of two as large, the first found";

  pbdrr::DicomSeriesList single;
  single.Series = { { "", { "x1", "x2" } } };
  notes.clear();
  EXPECT_EQ(&pbdrr::SelectDicomSeries(single, "", "DIR", notes), &single.Series[0]);
  EXPECT_TRUE(notes.empty()) << "one series: nothing to say";
}

TEST(PbdrrDicomSeriesSelection, AUIDSelectsItsSeriesOrListsThoseAvailable)
{
  const pbdrr::DicomSeriesList list = TwoSeries();
  std::vector<std::string>     notes;
  EXPECT_EQ(pbdrr::SelectDicomSeries(list, "2.25.1", "DIR", notes).Files.size(), 3u);
  EXPECT_TRUE(notes.empty());
  try
  {
    pbdrr::SelectDicomSeries(list, "2.25.9", "DIR", notes);
    ADD_FAILURE() << "an unknown series was selected";
  }
  catch (const std::runtime_error & e)
  {
    EXPECT_STREQ(e.what(), "series 2.25.9 is not in DIR; available:\n  2.25.1 (3 files)\n  2.25.2 (5 files)");
  }
}
