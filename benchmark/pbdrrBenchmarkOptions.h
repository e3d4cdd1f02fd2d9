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
#ifndef pbdrrBenchmarkOptions_h
#define pbdrrBenchmarkOptions_h
// The command line of PointBasedDRRBenchmark (--help prints Usage) and the names and sample counts it derives.
#include "itkPointBasedDRREnums.h"

#include <cstdint>
#include <string>
#include <vector>

namespace pbdrr
{
namespace bench
{
using KernelEnum = itk::PointBasedDRREnums::ReconstructionKernel;
using SplatEnum = itk::PointBasedDRREnums::Splat;

struct Options
{
  std::string              Input, OutputDirectory, Mode{ "trade" }, Name, WorkDirectory, Description;
  unsigned int             Columns{ 256 }, Rows{ 0 };
  double                   Spacing{ 2.4 }, Gantry{ 90.0 }, Sad{ 1000.0 }, Sid{ 1500.0 };
  std::vector<std::string> Samplers;
  std::vector<KernelEnum>  Kernels{ KernelEnum::Box, KernelEnum::Tent };
  std::vector<SplatEnum>   Splats{ SplatEnum::Nearest, SplatEnum::Bilinear };
  double                   MinSamples{ 1e5 }, MaxSamples{ 1e9 }, Budget{ 60.0 }, RepeatLimit{ 10.0 };
  unsigned int             Runs{ 3 }, ReferenceRays{ 8 }, Threads{ 0 };
  std::vector<unsigned>    ExactRays{ 1, 2, 4 };
  bool                     Itk{ true }, Plastimatch{ true }, SaveImages{ false };
  std::string              PlastimatchExe{ "plastimatch" };
  uint64_t                 Seed{ 1 };
  double                   ScalingSamples{ 1e7 };
  std::vector<double>      VolumeFractions{ 0.125, 0.25, 0.5, 1.0 };
  std::vector<unsigned>    DetectorColumns{ 64, 128, 256, 512, 1024 };
  unsigned int             CollimatedColumns{ 64 };
};

/** The options of argv; prints the usage and exits on -h or --help; throws std::runtime_error on a wrong one. */
Options
ParseOptions(int argc, char * argv[]);

/** 1, 3, 10, 30, ... x 10^k between min and max (inclusive). */
std::vector<uint64_t>
SampleLadder(double minimum, double maximum);

const char *
KernelName(KernelEnum kernel);
const char *
SplatName(SplatEnum splat);
} // namespace bench
} // namespace pbdrr

#endif
