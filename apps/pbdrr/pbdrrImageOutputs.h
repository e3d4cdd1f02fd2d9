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
#ifndef pbdrrImageOutputs_h
#define pbdrrImageOutputs_h

#include "pbdrrOptions.h"

#include "itkDRRProjectionGeometry.h"
#include "itkImage.h"

#include <string>
#include <vector>

namespace pbdrr
{
/** A DRR: line integrals (dimensionless) on the detector's pixels. */
using ProjectionType = itk::Image<float, 2>;

/** The output kind an extension stands for: "png" (gray levels) or "float". Throws UsageError for others. */
std::string
OutputKind(const std::string & path);

/** The output mode: --output-mode, or the output extension's own; refuses a mode the extension cannot hold. */
std::string
OutputMode(const Options & options);

/** Throws unless a file can be written at path (checked without creating anything). */
void
CheckWritable(const std::string & path);

/** Writes options.output (and options.standardErrorOutput if standardError is not null) in the output mode, each
 * through a temporary name renamed when whole; notes gets the gray window chosen, if any. */
void
WriteOutputs(const Options &            options,
             const ProjectionType *     lineIntegral,
             const ProjectionType *     standardError,
             std::vector<std::string> & notes);

/** The path of the view beside output: output's stem (without .mha, .nii.gz, ...) + ".geometry.txt". */
std::string
GeometryPathBeside(const std::string & output);

/** Writes the view beside output (output's stem + ".geometry.txt": the keys --geometry reads and, as comments, the
 * 3 x 4 projection matrix), through a temporary name; returns its path. */
std::string
WriteGeometryBeside(const std::string & output, const itk::DRRProjectionGeometry * geometry);
} // namespace pbdrr

#endif
