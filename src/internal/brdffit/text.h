// Escaping of text for the XML brdffit writes (MaterialX, Mitsuba), and its reverse for the XML it
// reads; the escaping for terminals, HTML, Markdown and CSV is public (error.h, io.h). All of it
// is implemented in text.cc.
#pragma once

#include <string>

namespace brdffit {

// Characters that can stand in XML 1.0 text: markup escaped as by escape_markup, and every byte
// that is not part of well-formed UTF-8, is a control character other than tab and newline, DEL,
// or part of U+FFFE or U+FFFF written as "\xNN".
std::string xml_text(const std::string& text);

// Text inside an XML comment: as xml_text, and no "--" (which would end it).
std::string xml_comment_text(const std::string& text);

// An attribute value of an XML file as text: the named entities (&amp; &lt; &gt; &quot; &apos;)
// and character references (&#N; &#xN;) replaced, a reference to anything but 1 to 127 by '?'
// (the names and numbers material files hold are ASCII). Throws Error naming `path` for a '&'
// without ';' or an unknown entity.
std::string xml_unescape(const std::string& text, const std::string& path);

// A name for an XML id or a MaterialX element: letters, digits and '_' only, not starting with a
// digit ("m_" prepended).
std::string xml_name(const std::string& name);

}  // namespace brdffit
