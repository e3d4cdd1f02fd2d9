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
// Force-included (-include) in the clang fuzz build only (POINTBASEDDRR_BUILD_FUZZERS).
//
// Debian's ITK 5.2 generated its itk_compiler_detection.h for GCC alone: under clang it stops with "Unsupported
// compiler". Clang implements the GNU dialect, so the detection is read once here as by GCC 12 (the compiler that
// built Debian's ITK); its include guard then keeps ITK from reading it again. Nothing else sees the disguise.
#if defined(__cplusplus) && defined(__clang__) && !defined(ITK_COMPILER_DETECTION_H)
#pragma push_macro("__clang__")
#pragma push_macro("__GNUC__")
#pragma push_macro("__GNUC_MINOR__")
#undef __clang__
#undef __GNUC__
#undef __GNUC_MINOR__
#define __GNUC__ 12
#define __GNUC_MINOR__ 2
#include <itk_compiler_detection.h>
#pragma pop_macro("__GNUC_MINOR__")
#pragma pop_macro("__GNUC__")
#pragma pop_macro("__clang__")
#endif
