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
#ifndef itkDRRDOMNodeXMLReader_h
#define itkDRRDOMNodeXMLReader_h

#include "itkDOMNodeXMLReader.h"
#include "itkDRRCompatibility.h"

#include <map>
#include <string>
#include <vector>

namespace itk
{
/** \class DRRDOMNodeXMLReader
 * \brief ITK's DOMNodeXMLReader (expat), with what reading RTK's geometry files needs of it (internal to
 * DRRRTKGeometryFileIO).
 *
 * ITK's reader parses with expat into an itk::DOMNode tree. It is used as it is, with three additions made in its
 * virtual callbacks, since ITK's reader gives expat the text as an unfinished document and keeps only trimmed pieces
 * of character data:
 * - a document cut off inside an element, which expat does not report then, is refused ("truncated XML");
 * - an element's character data is kept whole, as one text child per run between child elements (ITK's reader trims
 *   each piece expat hands over, and expat breaks text at line ends and character references: "5&#48;" would read as
 *   "5" and "0", a matrix's rows would run together);
 * - elements nested more than GetMaximumDepth() deep are refused (the DOMNode tree is released recursively).
 *
 * Errors are itk::ExceptionObject whose description opens with the `where` given to Parse() and names the open
 * element by its path (/RTKThreeDCircularGeometry/Projection[2]/Matrix[1], counted from 1 as in XPath): expat's
 * messages, which ITK's reader passes on, carry no line.
 *
 * \ingroup PointBasedDRR
 */
class DRRDOMNodeXMLReader : public DOMNodeXMLReader
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(DRRDOMNodeXMLReader);

  using Self = DRRDOMNodeXMLReader;
  using Superclass = DOMNodeXMLReader;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  itkNewMacro(Self);
  itkOverrideGetNameOfClassMacro(DRRDOMNodeXMLReader);

  /** The deepest nesting of elements read (the root is at depth 1). */
  static constexpr unsigned int
  GetMaximumDepth()
  {
    return 32;
  }

  /** Parses text into GetOutput(), the root element. Throws for text that is not an XML document, is not
   * well-formed, is cut off, or nests elements deeper than GetMaximumDepth(); where opens the description. */
  void
  Parse(const std::string & text, const std::string & where);

  /** An element's child elements (its text excluded), in order. */
  static std::vector<const DOMNode *>
  GetElements(const DOMNode & element);

  /** An element's character data (its children's excluded), as read. */
  static std::string
  GetText(const DOMNode & element);

  /** ITK's callbacks, with the additions above. */
  void
  StartElement(const char * name, const char ** attributes) override;
  void
  EndElement(const char * name) override;
  void
  CharacterDataHandler(const char * text, int length) override;

protected:
  DRRDOMNodeXMLReader() = default;
  ~DRRDOMNodeXMLReader() override = default;

private:
  /** An element started and not yet ended, with its character data since its last child. */
  struct OpenElement
  {
    DOMNode *                           Node;
    std::string                         Path;
    std::string                         Text;
    std::map<std::string, unsigned int> ChildrenNamed;
  };

  // Moves the innermost open element's character data into a text child of it (none if it is only white space).
  void
  KeepText();

  std::vector<OpenElement> m_Open;
  unsigned int             m_DepthBeyondMaximum{ 0 };
  bool                     m_TooDeep{ false };
  std::string              m_RootName;
};
} // namespace itk

#endif
