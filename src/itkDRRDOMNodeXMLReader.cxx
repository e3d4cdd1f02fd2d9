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
#include "itkDRRDOMNodeXMLReader.h"

#include "itkDOMTextNode.h"

#include <algorithm>
#include <cctype>
#include <sstream>

namespace itk
{
namespace
{
[[noreturn]] void
ThrowXMLError(const std::string & where, const std::string & message)
{
  ExceptionObject e(__FILE__, __LINE__, where + message, ITK_LOCATION);
  throw e;
}

bool
IsSpace(const std::string & text)
{
  return std::all_of(text.begin(), text.end(), [](unsigned char c) { return std::isspace(c) != 0; });
}
} // namespace

void
DRRDOMNodeXMLReader::Parse(const std::string & text, const std::string & where)
{
  m_Open.clear();
  m_DepthBeyondMaximum = 0;
  m_TooDeep = false;
  m_RootName.clear();
  std::istringstream stream(text);
  try
  {
    this->Update(stream);
  }
  catch (const ExceptionObject & e)
  {
    // expat's message (ITK's reader passes it on): where it stopped is the innermost open element.
    const std::string expat = std::string(" (expat: ") + e.GetDescription() + ")";
    if (m_RootName.empty())
    {
      ThrowXMLError(where, "not an XML document" + expat);
    }
    if (m_Open.empty()) // the root element ended: the root is open until then (it is never beyond the maximum depth)
    {
      ThrowXMLError(where, "not well-formed XML: content after the root element <" + m_RootName + ">" + expat);
    }
    ThrowXMLError(where, "not well-formed XML" + expat + " in " + m_Open.back().Path);
  }
  if (m_RootName.empty())
  {
    ThrowXMLError(where, "not an XML document: no root element");
  }
  if (!m_Open.empty())
  {
    // ITK's reader gives expat the text as an unfinished document, so expat waits for more instead of failing.
    ThrowXMLError(where, "truncated XML: " + m_Open.back().Path + " is not closed");
  }
  if (m_TooDeep)
  {
    ThrowXMLError(where, "elements nested more than " + std::to_string(GetMaximumDepth()) + " deep");
  }
}

std::vector<const DOMNode *>
DRRDOMNodeXMLReader::GetElements(const DOMNode & element)
{
  std::vector<const DOMNode *> elements;
  for (DOMNode::IdentifierType i = 0; i < static_cast<DOMNode::IdentifierType>(element.GetNumberOfChildren()); ++i)
  {
    if (element.GetTextChild(i) == nullptr)
    {
      elements.push_back(element.GetChild(i));
    }
  }
  return elements;
}

std::string
DRRDOMNodeXMLReader::GetText(const DOMNode & element)
{
  std::string text;
  for (DOMNode::IdentifierType i = 0; i < static_cast<DOMNode::IdentifierType>(element.GetNumberOfChildren()); ++i)
  {
    if (const auto * textNode = element.GetTextChild(i))
    {
      text += textNode->GetText();
    }
  }
  return text;
}

void
DRRDOMNodeXMLReader::StartElement(const char * name, const char ** attributes)
{
  if (m_Open.size() >= GetMaximumDepth() || m_DepthBeyondMaximum > 0)
  {
    ++m_DepthBeyondMaximum;
    m_TooDeep = true;
    return;
  }
  std::string path = "/" + std::string(name);
  DOMNode *   node = this->GetOutput();
  if (!m_Open.empty())
  {
    this->KeepText();
    path = m_Open.back().Path + path + "[" + std::to_string(++m_Open.back().ChildrenNamed[name]) + "]";
  }
  Superclass::StartElement(name, attributes);
  if (!m_Open.empty())
  {
    DOMNode * parent = m_Open.back().Node;
    node = parent->GetChild(static_cast<DOMNode::IdentifierType>(parent->GetNumberOfChildren()) - 1);
  }
  else
  {
    m_RootName = name;
  }
  m_Open.push_back({ node, path, std::string(), {} });
}

void
DRRDOMNodeXMLReader::EndElement(const char * name)
{
  if (m_DepthBeyondMaximum > 0)
  {
    --m_DepthBeyondMaximum;
    return;
  }
  this->KeepText();
  m_Open.pop_back();
  Superclass::EndElement(name);
}

void
DRRDOMNodeXMLReader::CharacterDataHandler(const char * text, int length)
{
  // Not ITK's handler, which trims each piece and keeps it as a text child of its own.
  if (m_DepthBeyondMaximum == 0 && !m_Open.empty())
  {
    m_Open.back().Text.append(text, static_cast<size_t>(length));
  }
}

void
DRRDOMNodeXMLReader::KeepText()
{
  OpenElement & open = m_Open.back();
  if (!IsSpace(open.Text))
  {
    open.Node->AddTextChildAtEnd(open.Text);
  }
  open.Text.clear();
}
} // namespace itk
