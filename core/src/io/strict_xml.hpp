// Strict reading of redpost's XML definitions (cells, KRL template sets): shared by their
// loaders so that every definition file reports problems the same way, "file:line: what".
//
// Internal to redpost::core; not installed.
#pragma once

#include <tinyxml2.h>

#include <cctype>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>

#include "redpost/io/error.hpp"

namespace redpost::detail {

struct XmlProblem {
  int line = 0;
  std::string what;
};

// The first thing in `text` that the XML standard refuses and tinyxml2 reads without a word: a
// comment that holds "--" (or ends in "--->"), a '<' in an attribute value, a bare '&' or an
// entity XML does not define without a DTD (io/xml_lexical.cpp). Nothing: none found.
std::optional<XmlProblem> find_xml_lexical_problem(std::string_view text);

class StrictXml {
 public:
  explicit StrictXml(std::string source) : source_(std::move(source)) {}

  [[noreturn]] void fail(int line, const std::string& what) const {
    throw Error(ErrorCode::bad_input, what, SourceLocation{source_, line, 0});
  }
  [[noreturn]] void fail(const tinyxml2::XMLElement* e, const std::string& what) const {
    fail(e ? e->GetLineNum() : 0, what);
  }

  // Rejects attributes that the element does not know: a typo must not be silently ignored.
  void only_attributes(const tinyxml2::XMLElement* e,
                       std::initializer_list<std::string_view> known) const {
    for (const tinyxml2::XMLAttribute* a = e->FirstAttribute(); a; a = a->Next()) {
      bool ok = false;
      for (auto k : known)
        ok = ok || k == a->Name();
      if (!ok) {
        std::string list;
        for (auto k : known)
          list += (list.empty() ? "" : ", ") + std::string(k);
        fail(e, std::string("<") + e->Name() + "> has an unknown attribute '" + a->Name() +
                    "' (known: " + (list.empty() ? "none" : list) + ")");
      }
    }
  }

  const char* required(const tinyxml2::XMLElement* e, const char* name) const {
    const char* v = e->Attribute(name);
    if (!v)
      fail(e, std::string("<") + e->Name() + "> needs the attribute '" + name + "'");
    return v;
  }

  // Parses `text` into `doc` and returns its root element, which must be <root_name>. An empty
  // file, XML that is not well-formed (by the standard, not only by tinyxml2), or another root
  // is an error at its line.
  const tinyxml2::XMLElement* parse(tinyxml2::XMLDocument& doc, const std::string& text,
                                    const char* root_name) const {
    const std::string empty = std::string("empty file: no <") + root_name + "> element";
    if (text.find_first_not_of(" \t\r\n") == std::string::npos)
      fail(0, empty);
    if (doc.Parse(text.data(), text.size()) != tinyxml2::XML_SUCCESS) {
      // tinyxml2 names the error XML_ERROR_MISMATCHED_ELEMENT etc. and appends its own
      // "Line number=N: detail"; keep the name in words and the detail.
      std::string what = doc.ErrorName();
      if (what.rfind("XML_ERROR_", 0) == 0)
        what = what.substr(10);
      for (char& c : what) {
        c = c == '_' ? ' ' : static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      }
      const std::string full = doc.ErrorStr() ? doc.ErrorStr() : "";
      const size_t detail = full.find(": ", full.find("Line number="));
      if (detail != std::string::npos)
        what += " (" + full.substr(detail + 2) + ")";
      fail(doc.ErrorLineNum(), "not well-formed XML: " + what);
    }
    if (const std::optional<XmlProblem> p = find_xml_lexical_problem(text))
      fail(p->line, p->what);
    const tinyxml2::XMLElement* root = doc.RootElement();
    if (!root)
      fail(0, empty);
    if (std::string_view(root->Name()) != root_name) {
      fail(root,
           std::string("the root element is <") + root->Name() + ">, expected <" + root_name + ">");
    }
    // tinyxml2 reads a second element after the root without a word: one root per file.
    if (const tinyxml2::XMLElement* more = root->NextSiblingElement()) {
      fail(more, std::string("a second root element <") + more->Name() + "> after </" + root_name +
                     ">: one <" + root_name + "> per file");
    }
    return root;
  }

  const std::string& source() const { return source_; }

 private:
  std::string source_;
};

}  // namespace redpost::detail
