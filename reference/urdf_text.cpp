#include "reference/urdf_text.hpp"

#include <stdexcept>

#include <tinyxml.h>

namespace em {

void removeGeometry(TiXmlDocument& doc, const std::vector<std::string>& locked) {
  TiXmlElement* robot = doc.RootElement();
  if (!robot) throw std::runtime_error("the URDF does not parse as XML");
  for (TiXmlElement* link = robot->FirstChildElement("link"); link; link = link->NextSiblingElement("link"))
    for (const char* tag : {"visual", "collision"})
      while (TiXmlElement* e = link->FirstChildElement(tag)) link->RemoveChild(e);
  for (TiXmlElement* j = robot->FirstChildElement("joint"); j; j = j->NextSiblingElement("joint"))
    for (const std::string& name : locked)
      if (j->Attribute("name") && name == j->Attribute("name")) j->SetAttribute("type", "fixed");
}

std::string urdfWithoutGeometry(const std::string& text, const std::vector<std::string>& locked) {
  TiXmlDocument doc;
  doc.Parse(text.c_str());
  removeGeometry(doc, locked);
  TiXmlPrinter printer;
  doc.Accept(&printer);
  return printer.CStr();
}

}  // namespace em
