#include "aperture/tools/viewer/view_panel.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include <imgui.h>

#include "aperture/tools/horizon_option.h"

namespace aal {

namespace {

void sunControls(ViewLighting& l) {
  int source = l.fromTime ? 0 : 1;
  ImGui::RadioButton("date, time, place", &source, 0);
  ImGui::SameLine();
  ImGui::RadioButton("azimuth/elevation", &source, 1);
  l.fromTime = source == 0;
  if (l.fromTime) {
    int date[3] = {l.year, l.month, l.day};
    if (ImGui::InputInt3("date (y m d)", date)) {
      l.year = date[0];
      l.month = date[1];
      l.day = date[2];
    }
    float hour = static_cast<float>(l.hourUtc);
    const int minutes = static_cast<int>(std::lround(l.hourUtc * 60)) % (24 * 60);
    char label[32];
    std::snprintf(label, sizeof label, "%02d:%02d UTC", minutes / 60, minutes % 60);
    if (ImGui::SliderFloat("time of day", &hour, 0.0f, 24.0f, label)) l.hourUtc = hour;
    if (ImGui::Button(l.playing ? "pause" : "play")) l.playing = !l.playing;
    ImGui::SameLine();
    float speed = static_cast<float>(l.hoursPerSecond);
    if (ImGui::SliderFloat("hours/s", &speed, 0.01f, 4.0f, "%.2f", ImGuiSliderFlags_Logarithmic)) {
      l.hoursPerSecond = speed;
    }
    float place[2] = {static_cast<float>(l.latitudeDeg), static_cast<float>(l.longitudeDeg)};
    if (ImGui::InputFloat2("lat, lon (deg)", place, "%.4f")) {
      l.latitudeDeg = std::clamp(double(place[0]), -90.0, 90.0);
      l.longitudeDeg = std::clamp(double(place[1]), -180.0, 180.0);
    }
  } else {
    float azimuth = static_cast<float>(l.sunAzimuthDeg);
    float elevation = static_cast<float>(l.sunElevationDeg);
    if (ImGui::SliderFloat("azimuth (deg)", &azimuth, 0.0f, 360.0f)) l.sunAzimuthDeg = azimuth;
    if (ImGui::SliderFloat("elevation (deg)", &elevation, -10.0f, 90.0f))
      l.sunElevationDeg = elevation;
  }
  float radius = static_cast<float>(l.sunRadiusDeg);
  if (ImGui::SliderFloat("sun radius (deg)", &radius, 0.05f, 10.0f, "%.3f",
                         ImGuiSliderFlags_Logarithmic)) {
    l.sunRadiusDeg = radius;
  }
  float turbidity = static_cast<float>(l.turbidity);
  if (ImGui::SliderFloat("turbidity", &turbidity, 2.0f, 10.0f)) l.turbidity = turbidity;
  ImGui::SliderFloat("sun intensity", &l.sunIntensity, 0.0f, 4.0f);
  ImGui::SliderFloat("sky intensity", &l.skyIntensity, 0.0f, 4.0f);
  ImGui::SliderFloat("exposure (stops)", &l.exposureStops, -6.0f, 6.0f, "%+.1f");
}

void shadingControls(ViewPanelModel& m) {
  const char* current = "?";
  for (const auto& [name, mode] : toolShadingModes()) {
    if (mode == m.mode) current = name.c_str();
  }
  if (ImGui::BeginCombo("shading", current)) {
    for (const auto& [name, mode] : toolShadingModes()) {
      // The horizon mode needs the DEM's directional horizons.
      if (mode == ShadingMode::Horizon && !m.horizonsMissing.empty()) {
        const std::string label = name + " (" + m.horizonsMissing + ")";
        ImGui::Selectable(label.c_str(), false, ImGuiSelectableFlags_Disabled);
        continue;
      }
      if (ImGui::Selectable(name.c_str(), mode == m.mode)) m.mode = mode;
    }
    ImGui::EndCombo();
  }
  if (m.bakeProgress) ImGui::TextDisabled("baseline-lambert until the aperture map is baked");
  // Fewer probes are faster on a CPU and blur oblique views.
  ImGui::SliderInt("anisotropy", &m.anisotropy, 1, kMaxFootprintProbes,
                   m.anisotropy == 1 ? "1 (trilinear)" : "%d probes");
  m.anisotropy = std::clamp(m.anisotropy, 1, kMaxFootprintProbes);
  ObscuranceSettings& o = m.obscurance;
  ImGui::Checkbox("obscurance", &o.enabled);
  char radiusLabel[48];
  std::snprintf(radiusLabel, sizeof radiusLabel, o.radiusM > 0 ? "%.0f" : "auto (%.0f)",
                o.radiusM > 0 ? o.radiusM : m.defaultObscuranceRadiusM);
  ImGui::SliderFloat("radius R (m)", &o.radiusM, 0.0f, m.maxObscuranceRadiusM, radiusLabel,
                     ImGuiSliderFlags_Logarithmic);
  o.radiusM = std::clamp(o.radiusM, 0.0f, m.maxObscuranceRadiusM);
  int samples = o.samples == 8 ? 0 : o.samples == 32 ? 2 : 1;
  ImGui::Combo("samples n", &samples,
               "8\0"
               "16\0"
               "32\0");
  o.samples = samples == 0 ? 8 : samples == 2 ? 32 : 16;
  ImGui::SliderInt("steps m", &o.steps, 1, 2);
  ImGui::Checkbox("interleaved 4x4 + filter", &o.interleaved);
}

void statusLines(const ViewPanelModel& m) {
  ImGui::TextWrapped("%s  %d x %d, %zu triangles", m.demName.c_str(), m.demWidth, m.demHeight,
                     m.triangles);
  if (m.bakeProgress) {
    char label[48];
    std::snprintf(label, sizeof label, "baking apertures %.0f%%", *m.bakeProgress * 100);
    ImGui::ProgressBar(static_cast<float>(*m.bakeProgress), ImVec2(-1, 0), label);
  }
  if (!m.message.empty()) ImGui::TextWrapped("%s", m.message.c_str());
}

void timings(ViewPanelModel& m, bool& changed) {
  ImGui::Text("%.1f fps, %.1f ms per frame", m.framesPerSecond, m.frameMs);
  ImGui::Text("resolution %.0f %% (drawn only when the view changes)", m.resolutionScale * 100);
  float target = static_cast<float>(m.targetFps);
  if (ImGui::SliderFloat("target fps", &target, 0.0f, 60.0f, target > 0 ? "%.0f" : "off")) {
    m.targetFps = target < 1 ? 0 : target;
  }
  changed = ImGui::Checkbox("rebuild smaller frames", &m.temporal);
  if (ImGui::IsItemHovered()) {
    ImGui::SetTooltip(
        "Frames drawn below full resolution are rebuilt from the frames before\n"
        "(sharper in motion); off: scaled up (cheaper on a CPU device).");
  }
  for (const auto& [pass, ms] : m.passMs) ImGui::Text("  gpu %-10s %7.2f ms", pass.c_str(), ms);
}

}  // namespace

ViewPanelActions drawViewPanel(ViewPanelModel& m) {
  ViewPanelActions actions;
  const float scale = ImGui::GetFontSize() / 13.0f;
  const float displayHeight = ImGui::GetIO().DisplaySize.y;
  ImGui::SetNextWindowPos(ImVec2(8 * scale, 8 * scale), ImGuiCond_FirstUseEver);
  // As tall as its contents, but never beyond the window: it scrolls then.
  ImGui::SetNextWindowSizeConstraints(
      ImVec2(380 * scale, 0), ImVec2(380 * scale, std::max(displayHeight - 16 * scale, 100.0f)));
  if (!ImGui::Begin("aal-view", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
    ImGui::End();
    return actions;
  }
  ImGui::PushItemWidth(-150 * scale);  // room for the labels
  statusLines(m);
  if (ImGui::CollapsingHeader("sun and sky", ImGuiTreeNodeFlags_DefaultOpen))
    sunControls(m.lighting);
  if (ImGui::CollapsingHeader("shading", ImGuiTreeNodeFlags_DefaultOpen)) shadingControls(m);
  if (ImGui::CollapsingHeader("camera", ImGuiTreeNodeFlags_DefaultOpen)) {
    ImGui::Text("%s, %.0f m above ground, %.0f m/s",
                m.cameraMode == CameraMode::Fly ? "fly" : "orbit", m.heightAboveGroundM,
                m.speedMps);
    actions.frameDem = ImGui::Button("frame DEM (F)");
    ImGui::SameLine();
    actions.toggleOrbit = ImGui::Button(m.cameraMode == CameraMode::Fly ? "orbit (O)" : "fly (O)");
    ImGui::SameLine();
    actions.screenshot = ImGui::Button("screenshot (F12)");
    actions.vsyncChanged = ImGui::Checkbox("vsync", &m.vsync);
  }
  if (ImGui::CollapsingHeader("timings", ImGuiTreeNodeFlags_DefaultOpen)) {
    timings(m, actions.temporalChanged);
  }
  ImGui::PopItemWidth();
  ImGui::End();
  return actions;
}

}  // namespace aal
