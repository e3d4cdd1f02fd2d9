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
#ifndef itkDRRXMLSubsetParser_h
#define itkDRRXMLSubsetParser_h

#include "itkMacro.h"

#include <algorithm>
#include <cctype>
#include <string>
#include <utility>
#include <vector>

namespace itk
{
/** \class DRRXMLSubsetParser
 * \brief A parser of the subset of XML 1.0 that RTK's geometry files use (internal to DRRRTKGeometryFileIO).
 *
 * It parses RTK's geometry files rather than ITKIOXML (itk::DOMNodeXMLReader, expat) does: RTK's geometry
 * uses a small subset of XML (a declaration, a DOCTYPE without internal subset, elements, attributes, character data,
 * comments), and the parser keeps the library's dependencies at ITKCommon and ITKTransform (no new ITK module, expat
 * library or find_package() component for the stand-alone, installed and fuzzing builds) while it reports every
 * malformation, including a truncated file, with its line.
 *
 * Refuses, with the line, anything else it meets: a malformed tag, an unknown entity, a mismatched or missing end
 * tag, a second root, text outside the root. Errors are itk::ExceptionObject, their description where + "line N: ...".
 *
 * \ingroup PointBasedDRR
 */
class DRRXMLSubsetParser
{
public:
  /** One XML element: its name, attributes, character data (children's excluded), children and line. */
  struct Element
  {
    std::string                                      Name;
    std::vector<std::pair<std::string, std::string>> Attributes;
    std::string                                      Text;
    std::vector<Element>                             Children;
    size_t                                           Line{ 0 };
  };

  /** A parser of text; where opens every error's description (the file's name). text must outlive the parser. */
  DRRXMLSubsetParser(const std::string & text, const std::string & where) : m_Text(text), m_Where(where)
  {
    for (size_t i = 0; i < m_Text.size(); ++i)
    {
      if (m_Text[i] == '\n')
      {
        m_NewLines.push_back(i);
      }
    }
  }

  /** The root element of the document; throws for anything outside the subset. */
  Element
  Parse()
  {
    this->SkipMisc(true);
    if (m_Position >= m_Text.size())
    {
      this->Fail("not an XML document: no root element");
    }
    if (m_Text[m_Position] != '<')
    {
      this->Fail("not an XML document: text before the root element");
    }
    Element root = this->ParseElement(0);
    this->SkipMisc(false);
    if (m_Position < m_Text.size())
    {
      this->Fail("not well-formed XML: content after the root element <" + root.Name + ">");
    }
    return root;
  }

  /** The line (from 1) of a position of the text. */
  size_t
  LineAt(size_t position) const
  {
    return static_cast<size_t>(std::lower_bound(m_NewLines.begin(), m_NewLines.end(), position) - m_NewLines.begin()) +
           1;
  }

private:
  [[noreturn]] void
  Fail(const std::string & message) const
  {
    ExceptionObject e(__FILE__,
                      __LINE__,
                      m_Where + "line " + std::to_string(this->LineAt(std::min(m_Position, m_Text.size()))) + ": " +
                        message,
                      ITK_LOCATION);
    throw e;
  }

  bool
  StartsWith(const char * prefix) const
  {
    return m_Text.compare(m_Position, std::char_traits<char>::length(prefix), prefix) == 0;
  }

  void
  SkipSpace()
  {
    while (m_Position < m_Text.size() && std::isspace(static_cast<unsigned char>(m_Text[m_Position])))
    {
      ++m_Position;
    }
  }

  // Skips to just after terminator, or fails naming what is unterminated.
  void
  SkipPast(const char * terminator, const std::string & what)
  {
    const size_t end = m_Text.find(terminator, m_Position);
    if (end == std::string::npos)
    {
      this->Fail("truncated XML: " + what + " is not terminated by '" + terminator + "'");
    }
    m_Position = end + std::char_traits<char>::length(terminator);
  }

  // White space, comments and processing instructions (and, in the prolog, one DOCTYPE) between top-level items.
  void
  SkipMisc(bool prolog)
  {
    for (;;)
    {
      this->SkipSpace();
      if (this->StartsWith("<?"))
      {
        this->SkipPast("?>", "a processing instruction");
      }
      else if (this->StartsWith("<!--"))
      {
        this->SkipPast("-->", "a comment");
      }
      else if (prolog && this->StartsWith("<!DOCTYPE"))
      {
        const size_t end = m_Text.find('>', m_Position);
        if (end == std::string::npos)
        {
          this->Fail("truncated XML: the DOCTYPE is not terminated by '>'");
        }
        if (m_Text.find('[', m_Position) < end)
        {
          this->Fail("a DOCTYPE with an internal subset is not supported");
        }
        m_Position = end + 1;
      }
      else
      {
        return;
      }
    }
  }

  std::string
  ParseName()
  {
    const size_t start = m_Position;
    const auto   isNameCharacter = [](unsigned char c) {
      return std::isalnum(c) || c == '_' || c == ':' || c == '-' || c == '.' || c >= 0x80;
    };
    while (m_Position < m_Text.size() && isNameCharacter(static_cast<unsigned char>(m_Text[m_Position])))
    {
      ++m_Position;
    }
    if (m_Position == start || std::isdigit(static_cast<unsigned char>(m_Text[start])) || m_Text[start] == '-' ||
        m_Text[start] == '.')
    {
      if (m_Position >= m_Text.size())
      {
        this->Fail("truncated XML: a tag is cut off");
      }
      this->Fail("not well-formed XML: a tag without a valid name");
    }
    return m_Text.substr(start, m_Position - start);
  }

  // Character data up to the next '<' (or the quote ending an attribute value), entities decoded.
  std::string
  ParseCharacterData(char stop)
  {
    std::string result;
    while (m_Position < m_Text.size() && m_Text[m_Position] != stop && m_Text[m_Position] != '<')
    {
      if (m_Text[m_Position] != '&')
      {
        result += m_Text[m_Position++];
        continue;
      }
      const size_t semicolon = m_Text.find(';', m_Position);
      if (semicolon == std::string::npos || semicolon - m_Position > 12)
      {
        this->Fail("not well-formed XML: '&' that does not start an entity");
      }
      const std::string entity = m_Text.substr(m_Position + 1, semicolon - m_Position - 1);
      if (entity == "lt")
      {
        result += '<';
      }
      else if (entity == "gt")
      {
        result += '>';
      }
      else if (entity == "amp")
      {
        result += '&';
      }
      else if (entity == "quot")
      {
        result += '"';
      }
      else if (entity == "apos")
      {
        result += '\'';
      }
      else
      {
        // A numeric reference to an ASCII character; nothing else is meaningful in a geometry file.
        char *        end = nullptr;
        unsigned long code = 0;
        bool          valid = entity.size() > 1 && entity[0] == '#';
        if (valid)
        {
          const bool hexadecimal = entity[1] == 'x';
          const auto digits = entity.substr(hexadecimal ? 2 : 1);
          valid = !digits.empty() && std::isxdigit(static_cast<unsigned char>(digits[0]));
          if (valid)
          {
            code = std::strtoul(digits.c_str(), &end, hexadecimal ? 16 : 10);
            valid = *end == '\0' && code > 0 && code < 128;
          }
        }
        if (!valid)
        {
          this->Fail("unsupported entity '&" + entity + ";'");
        }
        result += static_cast<char>(code);
      }
      m_Position = semicolon + 1;
    }
    return result;
  }

  Element
  ParseElement(unsigned int depth)
  {
    if (depth > 32)
    {
      this->Fail("elements nested more than 32 deep");
    }
    Element element;
    element.Line = this->LineAt(m_Position);
    ++m_Position; // '<'
    element.Name = this->ParseName();
    for (;;)
    {
      const size_t before = m_Position;
      this->SkipSpace();
      if (m_Position >= m_Text.size())
      {
        this->Fail("truncated XML: the start tag <" + element.Name + "> is cut off");
      }
      if (this->StartsWith("/>"))
      {
        m_Position += 2;
        return element;
      }
      if (m_Text[m_Position] == '>')
      {
        ++m_Position;
        break;
      }
      if (m_Position == before)
      {
        this->Fail("not well-formed XML: in the start tag <" + element.Name + ">");
      }
      std::string name = this->ParseName();
      this->SkipSpace();
      if (m_Position >= m_Text.size() || m_Text[m_Position] != '=')
      {
        this->Fail("not well-formed XML: attribute '" + name + "' of <" + element.Name + "> has no value");
      }
      ++m_Position;
      this->SkipSpace();
      if (m_Position >= m_Text.size() || (m_Text[m_Position] != '"' && m_Text[m_Position] != '\''))
      {
        this->Fail("not well-formed XML: the value of attribute '" + name + "' is not quoted");
      }
      const char  quote = m_Text[m_Position++];
      std::string value = this->ParseCharacterData(quote);
      if (m_Position >= m_Text.size() || m_Text[m_Position] != quote)
      {
        this->Fail("not well-formed XML: the value of attribute '" + name + "' is not terminated");
      }
      ++m_Position;
      element.Attributes.emplace_back(std::move(name), std::move(value));
    }
    // Content.
    for (;;)
    {
      if (m_Position >= m_Text.size())
      {
        m_Position = m_Text.size();
        this->Fail("truncated XML: element <" + element.Name + "> (line " + std::to_string(element.Line) +
                   ") is not closed");
      }
      if (this->StartsWith("</"))
      {
        m_Position += 2;
        const std::string name = this->ParseName();
        this->SkipSpace();
        if (m_Position >= m_Text.size())
        {
          this->Fail("truncated XML: the end tag </" + name + "> is cut off");
        }
        if (name != element.Name || m_Text[m_Position] != '>')
        {
          this->Fail("not well-formed XML: </" + name + "> closes <" + element.Name + "> (line " +
                     std::to_string(element.Line) + ")");
        }
        ++m_Position;
        return element;
      }
      if (this->StartsWith("<!--"))
      {
        this->SkipPast("-->", "a comment");
      }
      else if (this->StartsWith("<![CDATA["))
      {
        m_Position += 9;
        const size_t end = m_Text.find("]]>", m_Position);
        if (end == std::string::npos)
        {
          this->Fail("truncated XML: a CDATA section is not terminated");
        }
        element.Text += m_Text.substr(m_Position, end - m_Position);
        m_Position = end + 3;
      }
      else if (this->StartsWith("<?"))
      {
        this->SkipPast("?>", "a processing instruction");
      }
      else if (this->StartsWith("<!"))
      {
        this->Fail("not well-formed XML: unexpected '<!' in <" + element.Name + ">");
      }
      else if (m_Text[m_Position] == '<')
      {
        element.Children.push_back(this->ParseElement(depth + 1));
      }
      else
      {
        element.Text += this->ParseCharacterData('<');
      }
    }
  }

  const std::string & m_Text;
  std::string         m_Where;
  std::vector<size_t> m_NewLines;
  size_t              m_Position{ 0 };
};
} // namespace itk

#endif
