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
#ifndef pbdrrRegisterCommand_h
#define pbdrrRegisterCommand_h

#include "pbdrrRegistration.h"

#include <string>
#include <vector>

namespace pbdrr
{
/** An X-ray of the command line and the view given for it (none: a localizer's header gives it). */
struct XRayArgument
{
  std::string Image;
  std::string GeometryFile;
  std::string MatrixFile;
};

/** What `pbdrr register` is told. */
struct RegisterOptions
{
  std::string               input;
  std::string               seriesUID;
  std::vector<XRayArgument> xrays;
  std::string               output; // OUT.png: the DRR at the pose; OUT.checkerboard.png beside it
  RegistrationSettings      settings;
  bool                      help{ false };
  bool                      quiet{ false };
};

/** Parses the arguments after `register` by its table of options (pbdrrRegisterOptions.cxx, declared and parsed as
 * pbdrr's are: pbdrrOptionTable.h); throws UsageError. --geometry and --projection-matrix give the view of the --xray
 * before them. */
RegisterOptions
ParseRegisterCommandLine(const std::vector<std::string> & arguments);

/** The text of pbdrr register --help: its options' from the same table, by the same code as pbdrr --help's. */
std::string
RegisterHelpText();

/** Loads the CT and the X-rays, registers, prints `pose: tx ty tz rx ry rz` and `similarity: NCC`, writes the images.
 */
void
RunRegister(const RegisterOptions & options);
} // namespace pbdrr

#endif
