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
#ifndef pbdrrApplication_h
#define pbdrrApplication_h

#include "pbdrrOptions.h"

namespace pbdrr
{
/** Loads, renders and writes as the options say. Throws std::runtime_error (or itk::ExceptionObject) on failure. */
void
Run(const Options & options);

std::string
VersionText();
} // namespace pbdrr

#endif
