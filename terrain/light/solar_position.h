// Position of the sun in the sky from a UTC date-time and a place: the NOAA
// solar position algorithm.
//
// Source: NOAA Global Monitoring Laboratory, "Solar Calculation Details" and its
// spreadsheet NOAA_Solar_Calculations_day.xls, which implement the low-accuracy
// solar coordinates of Meeus, "Astronomical Algorithms" (2nd ed., 1998): ch. 7
// (Julian Day), ch. 22 (mean obliquity, eq. 22.2), ch. 25 (eqs. 25.1-25.8), the
// equation of time of ch. 28 (Smart's formula, eq. 28.3) and the refraction
// correction of the NOAA spreadsheet (Saemundsson-like fit above 5°, polynomial
// near the horizon). Stated accuracy about 0.02° for years 1800-2100 (measured
// in tests/terrain/light/solar_position_test.cpp against Meeus example 25.a and the
// NREL SPA reference case of Reda & Andreas 2004).
//
// Conventions, as docs/design.md §1 and gdaldem: azimuth in degrees clockwise
// from north in [0, 360); elevation (altitude) in degrees above the horizon in
// [-90, 90]; latitude in degrees north positive, longitude in degrees east
// positive. Time is UTC; TT - UT (ΔT, about a minute) is ignored as NOAA does,
// which moves the sun by less than 0.001°.
#pragma once

#include <optional>
#include <string>

#include <glm/vec3.hpp>

namespace aal {

// A calendar date and time of day in UTC (proleptic Gregorian calendar).
struct UtcTime {
  int year = 2000;    // e.g. 2024
  int month = 1;      // 1..12
  int day = 1;        // 1..31 (valid for the month)
  int hour = 0;       // 0..23
  int minute = 0;     // 0..59
  double second = 0;  // [0, 60)

  bool operator==(const UtcTime&) const = default;
};

// Parses an ISO 8601 date-time into UTC. Accepted:
//   "2024-06-21T12:00:00Z", "2024-06-21T12:00Z", "2024-06-21 12:00:00",
//   fractional seconds "12:00:00.5", and offsets "+02:00", "-0530", "+02"
//   (the result is converted to UTC, crossing day/month/year boundaries as
//   needed). Without a zone designator the time is taken as UTC. Anything
//   else (other layouts, out-of-range fields such as 2023-02-29 or 24:00,
//   trailing text) gives std::nullopt.
std::optional<UtcTime> parseIso8601Utc(const std::string& text);

// Formats as "YYYY-MM-DDTHH:MM:SS(.sss)Z".
std::string formatIso8601Utc(const UtcTime& time);

// Seconds from `from` to `to` (negative when `to` is earlier), and the
// instant `seconds` after `time` (across day, month and year boundaries;
// proleptic Gregorian calendar, no leap seconds, like the rest of this file).
// aal-render --time-range spreads frames between two instants with them.
double secondsBetween(const UtcTime& from, const UtcTime& to);
UtcTime addSeconds(const UtcTime& time, double seconds);

// Julian Day (days since -4712-01-01 12:00 UT) of a UTC instant, Meeus eq. 7.1
// (Gregorian calendar). E.g. 2000-01-01T12:00Z -> 2451545.0.
double julianDay(const UtcTime& time);

struct SolarPosition {
  double azimuthDeg = 0;             // clockwise from north, [0, 360)
  double elevationDeg = 0;           // apparent: geometric + refraction, [-90, 90]
  double geometricElevationDeg = 0;  // without refraction
  double refractionDeg = 0;          // NOAA atmospheric refraction correction, >= 0
  double declinationDeg = 0;         // apparent declination of the sun
  double rightAscensionDeg = 0;      // apparent right ascension, [0, 360)
  double equationOfTimeMin = 0;      // apparent minus mean solar time, minutes (about ±16)
  double hourAngleDeg = 0;           // local hour angle, [-180, 180), 0 at solar noon, >0 afternoon
  double sunDistanceAu = 1;          // Earth-sun distance, astronomical units
};

// NOAA solar position (see the file comment) for a UTC instant and a place.
// latitudeDeg in [-90, 90], longitudeDeg east positive (any value; taken mod 360).
SolarPosition solarPosition(const UtcTime& time, double latitudeDeg, double longitudeDeg);

// The UTC instant of local solar noon (sun on the meridian) on the UTC date of
// `day` (its time of day is ignored) at longitudeDeg: 12:00 - 4 min/° ·
// longitude - equation of time (NOAA spreadsheet, "Solar Noon"). The result may
// fall on the previous or next UTC date for longitudes near ±180°.
UtcTime solarNoonUtc(const UtcTime& day, double longitudeDeg);

// Unit vector towards a sun at azimuthDeg (clockwise from north) and
// elevationDeg (above the horizon) in the world frame of docs/design.md §1:
// x = east, y = north, z = up.
glm::vec3 sunDirection(double azimuthDeg, double elevationDeg);

}  // namespace aal
