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
// The pieces of pbdrr's batches (issue 17): output patterns, views files, sweeps, the seeds of views, and the
// temporary names that make every write whole or absent. The batch's images themselves are checked end to end by
// pbdrr.batch_forms_give_the_same_images (BatchEquivalence.cmake).
#include "pbdrrBatch.h"
#include "pbdrrOptions.h"
#include "pbdrrOutputFiles.h"
#include "pbdrrView.h"
#include "pbdrrViewList.h"

#include "gtest/gtest.h"

#include <cstdio>
#include <fstream>
#include <set>
#include <unistd.h>

namespace
{
std::string
WriteTextFile(const std::string & name, const std::string & text)
{
  const std::string path = ::testing::TempDir() + "pbdrrBatchGTest_" + std::to_string(getpid()) + "_" + name;
  std::ofstream(path) << text;
  return path;
}
} // namespace

TEST(OutputPattern, CountersAreFormattedAsPrintfWould)
{
  EXPECT_EQ(pbdrr::OutputPattern("out/v_%04d.mha").Format(7), "out/v_0007.mha");
  EXPECT_EQ(pbdrr::OutputPattern("out/v_%04d.mha").Format(123456), "out/v_123456.mha");
  EXPECT_EQ(pbdrr::OutputPattern("v_%d.nii.gz").Format(42), "v_42.nii.gz");
  EXPECT_EQ(pbdrr::OutputPattern("v_%3d.mha").Format(5), "v_  5.mha");
  EXPECT_EQ(pbdrr::OutputPattern("100%%_%d.mha").Format(3), "100%_3.mha");
  EXPECT_TRUE(pbdrr::OutputPattern("v_%d.mha").HasCounter());
  EXPECT_FALSE(pbdrr::OutputPattern("v_100%%.mha").HasCounter());
  EXPECT_EQ(pbdrr::OutputPattern("v_100%%.mha").Format(9), "v_100%.mha");
}

TEST(OutputPattern, RefusesWhatIsNotOneCounter)
{
  for (const char * pattern : { "v_%s.mha", "v_%.mha", "v_%d_%d.mha", "v_%123d.mha", "v_%", "v_%ld.mha" })
  {
    EXPECT_THROW(pbdrr::OutputPattern{ pattern }, pbdrr::UsageError) << pattern;
  }
}

TEST(OutputFiles, TemporaryNamesAreHiddenBesideAndKeepTheExtension)
{
  const std::string pid = std::to_string(getpid());
  EXPECT_EQ(pbdrr::TemporaryPathBeside("out/v_0001.mha"), "out/.v_0001.partial-" + pid + ".mha");
  EXPECT_EQ(pbdrr::TemporaryPathBeside("v.nii.gz"), ".v.partial-" + pid + ".nii.gz");
  EXPECT_EQ(pbdrr::TemporaryPathBeside("/a.b/noextension"), "/a.b/.noextension.partial-" + pid);
}

TEST(OutputFiles, AWriteThatFailsLeavesNothing)
{
  const std::string path = ::testing::TempDir() + "pbdrrBatchGTest_atomic_" + std::to_string(getpid()) + ".txt";
  std::remove(path.c_str());
  EXPECT_THROW(pbdrr::WriteAtomically(path,
                                      [](const std::string & temporary) {
                                        std::ofstream(temporary) << "half";
                                        throw std::runtime_error("disk full");
                                      }),
               std::runtime_error);
  EXPECT_FALSE(pbdrr::FileExists(path));
  EXPECT_FALSE(pbdrr::FileExists(pbdrr::TemporaryPathBeside(path)));
  pbdrr::WriteAtomically(path, [](const std::string & temporary) { std::ofstream(temporary) << "whole"; });
  std::string text;
  std::ifstream(path) >> text;
  EXPECT_EQ(text, "whole");
  EXPECT_FALSE(pbdrr::FileExists(pbdrr::TemporaryPathBeside(path)));
  std::remove(path.c_str());
}

TEST(ViewList, ASweepStepsFromItsStart)
{
  const auto views = pbdrr::MakeSweep(4, 10.0, -2.5);
  ASSERT_EQ(views.size(), 4u);
  for (size_t k = 0; k < views.size(); ++k)
  {
    ASSERT_TRUE(views[k].GantryDegrees);
    EXPECT_EQ(*views[k].GantryDegrees, 10.0 - 2.5 * static_cast<double>(k));
    EXPECT_FALSE(views[k].Normal || views[k].Pose || views[k].Whole);
  }
}

TEST(ViewList, AViewsFileSetsWhatItsColumnsSay)
{
  const std::string path = WriteTextFile("views.csv",
                                         "# a comment, then the header (any case, spaces allowed)\n"
                                         "NRM_X, nrm_y, nrm_z, sad, output, tx, ty, tz, rx, ry, rz\n"
                                         "\n"
                                         "0, -1, 0, 800, ap.mha, 1, 2, 3, 4, 5, 6\n"
                                         ",,,,,,,,,,\n");
  const auto        views = pbdrr::ReadViewsFile(path);
  ASSERT_EQ(views.size(), 2u);
  EXPECT_EQ(views[0].Line, 4u);
  ASSERT_TRUE(views[0].Normal && views[0].Sad && views[0].Pose);
  EXPECT_EQ((*views[0].Normal)[1], -1.0);
  EXPECT_EQ(*views[0].Sad, 800.0);
  EXPECT_EQ(views[0].Output, "ap.mha");
  EXPECT_EQ((*views[0].Pose)[5], 6.0);
  EXPECT_FALSE(views[0].GantryDegrees || views[0].Sid || views[0].Isocenter);
  // Empty cells keep the command line's view.
  EXPECT_EQ(views[1].Line, 5u);
  EXPECT_FALSE(views[1].Normal || views[1].Sad || views[1].Pose);
  EXPECT_TRUE(views[1].Output.empty());

  pbdrr::Options commandLine;
  commandLine.gantryDegrees = 30.0;
  commandLine.sad = 1000.0;
  commandLine.sid = 1500.0;
  const auto first = pbdrr::MakeView(commandLine, views[0], nullptr);
  EXPECT_EQ(first->GetSourceToIsocenterDistance(), 800.0);
  EXPECT_EQ(first->GetSourceToDetectorDistance(), 1500.0);
  EXPECT_EQ(first->GetNormal()[1], -1.0);
  const auto second = pbdrr::MakeView(commandLine, views[1], nullptr);
  EXPECT_EQ(second->GetSourceToIsocenterDistance(), 1000.0);
  EXPECT_EQ(second->GetNormal(), pbdrr::MakeGeometry(commandLine, nullptr)->GetNormal());
  std::remove(path.c_str());
}

TEST(ViewList, AViewsGantryReplacesTheCommandLinesNormal)
{
  pbdrr::Options commandLine;
  commandLine.normal = std::array<double, 3>{ 0.0, 1.0, 0.0 };
  pbdrr::ViewSpec view;
  view.GantryDegrees = 0.0;
  const auto geometry = pbdrr::MakeView(commandLine, view, nullptr);
  EXPECT_EQ(geometry->GetNormal()[0], 1.0);
  EXPECT_EQ(geometry->GetGantryAngleInDegrees(), 0.0);
}

// Issue 28: a batch dropped the geometry file's pixels and gantry. The view is built in layers, the same for every
// mode: defaults, the file, the flags, the row; each changes only what it names.
TEST(MakeView, ARowChangesOnlyWhatItNamesOverTheFileAndTheFlags)
{
  const std::string file =
    WriteTextFile("view.txt", "cols 24\nrows 20\nspacing 2.4 2.2\ngantry 90\nsad 900\noffset 3 -1\nmirror 1\n");
  pbdrr::Options options;
  options.geometryFile = file;
  options.sid = 1400.0;
  const auto      single = pbdrr::MakeGeometry(options, nullptr);
  pbdrr::ViewSpec row;
  row.Sid = 1300.0;
  const auto view = pbdrr::MakeView(options, row, nullptr);
  for (const auto & geometry : { single, view })
  {
    EXPECT_EQ(geometry->GetDetectorSize()[0], 24u);
    EXPECT_EQ(geometry->GetDetectorSize()[1], 20u);
    EXPECT_EQ(geometry->GetDetectorSpacing()[0], 2.4);
    EXPECT_EQ(geometry->GetDetectorSpacing()[1], 2.2);
    EXPECT_EQ(geometry->GetGantryAngleInDegrees(), 90.0);
    EXPECT_EQ(geometry->GetSourceToIsocenterDistance(), 900.0);
    EXPECT_EQ(geometry->GetDetectorOffset()[0], 3.0);
    EXPECT_TRUE(geometry->GetColumnsMirrored());
  }
  EXPECT_EQ(single->GetSourceToDetectorDistance(), 1400.0); // the flag over the file
  EXPECT_EQ(view->GetSourceToDetectorDistance(), 1300.0);   // the row over the flag
  // A flag overrides the file in every mode: --size over cols and rows, the file's spacing kept.
  options.detectorSize = std::array<double, 2>{ 16.0, 12.0 };
  const auto sized = pbdrr::MakeView(options, row, nullptr);
  EXPECT_EQ(sized->GetDetectorSize()[0], 16u);
  EXPECT_EQ(sized->GetDetectorSpacing()[0], 2.4);
  std::remove(file.c_str());
}

TEST(MakeView, ASweepStartsAtTheFilesGantryAndRefusesItsNormal)
{
  const std::string gantry = WriteTextFile("gantry.txt", "gantry 90\n");
  pbdrr::Options    options;
  options.geometryFile = gantry;
  EXPECT_EQ(pbdrr::SweepStartDegrees(options), 90.0);
  options.gantryDegrees = 45.0;
  EXPECT_EQ(pbdrr::SweepStartDegrees(options), 45.0);
  const std::string normal = WriteTextFile("normal.txt", "nrm 0 1 0\n");
  options.gantryDegrees.reset();
  options.geometryFile = normal;
  try
  {
    pbdrr::SweepStartDegrees(options);
    ADD_FAILURE() << "a sweep over the file's nrm must be refused";
  }
  catch (const pbdrr::UsageError & e)
  {
    EXPECT_NE(std::string(e.what()).find("nrm in " + normal), std::string::npos) << e.what();
  }
  std::remove(gantry.c_str());
  std::remove(normal.c_str());
}

TEST(ViewList, BadFilesNameTheirLine)
{
  const std::pair<const char *, const char *> cases[] = {
    { "gantry\n0\n1e400\n", "line 3: gantry expects a finite number" },
    { "gantry,sid\n0,1500,7\n", "line 2: 3 cells, the header has 2" },
    { "gantry,gantry\n", "line 1: the column gantry is named twice" },
    { "iso_x,iso_y,iso_z\n1,2,\n", "line 2: iso_x .. iso_z are given together or left empty" },
    { "tx,ty\n", "the columns tx ty tz rx ry rz come together" },
  };
  for (const auto & c : cases)
  {
    const std::string path = WriteTextFile("bad.csv", c.first);
    try
    {
      pbdrr::ReadViewsFile(path);
      ADD_FAILURE() << "no error for " << c.first;
    }
    catch (const pbdrr::UsageError & e)
    {
      EXPECT_NE(std::string(e.what()).find(c.second), std::string::npos) << e.what();
    }
    std::remove(path.c_str());
  }
}

TEST(ViewSeed, EveryViewHasItsOwnSeedAndEverySeedItsOwnViews)
{
  std::set<uint64_t> seeds;
  for (uint64_t seed : { 0ull, 1ull, 42ull })
  {
    for (uint64_t k = 0; k < 1000; ++k)
    {
      seeds.insert(pbdrr::ViewSeed(seed, k));
    }
  }
  EXPECT_EQ(seeds.size(), 3000u);
  EXPECT_EQ(pbdrr::ViewSeed(7, 3), pbdrr::ViewSeed(7, 3));
}
