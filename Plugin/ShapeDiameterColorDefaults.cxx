// SPDX-License-Identifier: BSD-3-Clause
#include "ShapeDiameterColorDefaults.h"

#include "vtkSMSettings.h"

#include <array>
#include <locale>
#include <sstream>
#include <string>

namespace
{

constexpr int MaximumClusters = 16; // the partition filter's upper bound on k

// Kelly (1965), "Twenty-two colors for maximum contrast", without white, black and grey;
// most distinct first because small k is the common case.
constexpr std::array<unsigned int, MaximumClusters> PartColors = { 0x0067A5, 0xF38400, 0x008856,
  0xBE0032, 0x875692, 0xF3C300, 0xA1CAF1, 0xE68FAC, 0xC2B280, 0x882D17, 0x8DB600, 0x604E97,
  0xF99379, 0xDCD300, 0xB3446C, 0x654522 };

// Below site (1.0) and user settings, above ParaView's built-in defaults (0.0).
constexpr double SettingsPriority = 0.5;

std::string CategoricalLookupTable()
{
  std::ostringstream json;
  json.imbue(std::locale::classic());
  json << "{\"IndexedLookup\": 1, \"AnnotationsInitialized\": 1, "
          "\"ShowIndexedColorActiveValues\": 1, \"NanColor\": [0.5, 0.5, 0.5], "
          "\"Annotations\": [";
  for (int label = 0; label < MaximumClusters; ++label)
  {
    json << (label ? ", " : "") << '"' << label << "\", \"cluster " << label << '"';
  }
  json << "], \"IndexedColors\": [";
  for (int label = 0; label < MaximumClusters; ++label)
  {
    const unsigned int rgb = PartColors[label];
    json << (label ? ", " : "") << ((rgb >> 16) & 0xFF) / 255.0 << ", "
         << ((rgb >> 8) & 0xFF) / 255.0 << ", " << (rgb & 0xFF) / 255.0;
  }
  json << "]}";
  return json.str();
}

} // namespace

void ShapeDiameterRegisterColorDefaults()
{
  const std::string lookupTable = CategoricalLookupTable();
  std::ostringstream settings;
  settings.imbue(std::locale::classic());
  settings << "{\"array_lookup_tables\": {\"SDFCluster\": {\"PVLookupTable\": " << lookupTable
           << "}";
  for (int level = 1; level < MaximumClusters; ++level)
  {
    settings << ", \"SDFLevel" << level << "\": {\"PVLookupTable\": " << lookupTable << "}";
  }
  settings << "}}";
  vtkSMSettings::GetInstance()->AddCollectionFromString(settings.str(), SettingsPriority);
}
