// NOAA solar position (terrain/light/solar_position.h) against published values:
// Meeus's worked examples, the NREL SPA reference case, almanac sunrise times
// and the equation of time, plus conventions and ISO 8601 parsing.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <string>

#include <glm/geometric.hpp>

#include "aperture/terrain/light/solar_position.h"

namespace aal {
namespace {

UtcTime utc(int year, int month, int day, int hour = 0, int minute = 0, double second = 0) {
  return UtcTime{year, month, day, hour, minute, second};
}

UtcTime plusSeconds(const UtcTime& t, double seconds) {
  // Test helper via the parser's own normalisation: a whole offset in minutes.
  UtcTime out = t;
  out.second += seconds;
  while (out.second >= 60) {
    out.second -= 60;
    ++out.minute;
  }
  while (out.minute >= 60) {
    out.minute -= 60;
    ++out.hour;
  }
  return out;
}

// --- Julian Day -------------------------------------------------------------

TEST(JulianDay, J2000IsNoonOfFirstJanuary2000) {
  EXPECT_DOUBLE_EQ(julianDay(utc(2000, 1, 1, 12)), 2451545.0);
}

TEST(JulianDay, MatchesMeeusExamples) {
  // Meeus, Astronomical Algorithms, example 7.a: 1957 October 4.81 -> 2436116.31.
  EXPECT_NEAR(julianDay(utc(1957, 10, 4, 19, 26, 24)), 2436116.31, 1e-6);
  // Example 25.a: 1992 October 13.0 -> 2448908.5.
  EXPECT_DOUBLE_EQ(julianDay(utc(1992, 10, 13)), 2448908.5);
  // Example 7.a, second part: 333 January 27.5 (Julian calendar there; here the
  // proleptic Gregorian date 333-01-28 12:00 gives the same day) -> 1842713.0.
  EXPECT_DOUBLE_EQ(julianDay(utc(333, 1, 28, 12)), 1842713.0);
}

// --- ISO 8601 -----------------------------------------------------------------

// --time-range arithmetic: across a leap day, a year's end, and back; the
// Julian Day difference agrees.
TEST(UtcArithmetic, AddsAndMeasuresSecondsAcrossCalendarBoundaries) {
  const UtcTime a = *parseIso8601Utc("2024-02-28T23:30:00Z");
  const UtcTime b = addSeconds(a, 3600.0);
  EXPECT_EQ(formatIso8601Utc(b), "2024-02-29T00:30:00Z");
  EXPECT_EQ(formatIso8601Utc(addSeconds(a, 86400.0 + 1800.0)), "2024-03-01T00:00:00Z");
  const UtcTime newYear = *parseIso8601Utc("2024-12-31T23:59:30Z");
  EXPECT_EQ(formatIso8601Utc(addSeconds(newYear, 45.5)), "2025-01-01T00:00:15.500Z");
  EXPECT_EQ(formatIso8601Utc(addSeconds(newYear, -86400.0 * 366)), "2023-12-31T23:59:30Z");
  EXPECT_DOUBLE_EQ(secondsBetween(a, b), 3600.0);
  EXPECT_DOUBLE_EQ(secondsBetween(b, a), -3600.0);
  const UtcTime c = *parseIso8601Utc("2026-07-04T06:07:08Z");
  EXPECT_NEAR(secondsBetween(a, c), (julianDay(c) - julianDay(a)) * 86400.0, 1e-3);
  EXPECT_EQ(addSeconds(a, secondsBetween(a, c)), c);
}

TEST(Iso8601, AcceptsTheDocumentedLayouts) {
  const UtcTime noon = utc(2024, 6, 21, 12, 0, 0);
  for (const char* text :
       {"2024-06-21T12:00:00Z", "2024-06-21T12:00Z", "2024-06-21 12:00:00", "2024-06-21t12:00:00z",
        "2024-06-21T12:00:00+00:00", "2024-06-21T14:00:00+02:00", "2024-06-21T14:00+0200",
        "2024-06-21T14:00+02", "2024-06-21T06:30:00-05:30"}) {
    const std::optional<UtcTime> t = parseIso8601Utc(text);
    ASSERT_TRUE(t.has_value()) << text;
    EXPECT_EQ(*t, noon) << text;
  }
}

TEST(Iso8601, KeepsFractionalSeconds) {
  const std::optional<UtcTime> t = parseIso8601Utc("2024-06-21T12:34:56.25Z");
  ASSERT_TRUE(t.has_value());
  EXPECT_EQ(t->minute, 34);
  EXPECT_DOUBLE_EQ(t->second, 56.25);
}

TEST(Iso8601, OffsetsCrossDayMonthAndYearBoundaries) {
  EXPECT_EQ(parseIso8601Utc("2024-01-01T01:30:00+02:00"), utc(2023, 12, 31, 23, 30));
  EXPECT_EQ(parseIso8601Utc("2023-12-31T20:00:00-05:00"), utc(2024, 1, 1, 1, 0));
  EXPECT_EQ(parseIso8601Utc("2024-03-01T00:15+01:00"), utc(2024, 2, 29, 23, 15));  // leap year
  EXPECT_EQ(parseIso8601Utc("2023-03-01T00:15+01:00"), utc(2023, 2, 28, 23, 15));
}

TEST(Iso8601, RejectsGarbageAndOutOfRangeFields) {
  for (const char* text : {"",
                           "garbage",
                           "2024-06-21",
                           "2024-06-21T",
                           "2024-6-21T12:00Z",
                           "24-06-21T12:00Z",
                           "2024-06-21T12Z",
                           "2024-06-21T1:00Z",
                           "2024-06-21X12:00Z",
                           "2024-06-21T12:00:00ZZ",
                           "2024-06-21T12:00:00 ",
                           " 2024-06-21T12:00:00",
                           "2024-06-21T12:00:00+2",
                           "2024-06-21T12:00:00+24:00",
                           "2024-06-21T12:00:00+01:60",
                           "2024-06-21T12:00:00+01:",
                           "2024-06-21T12:00:00.Z",
                           "2024-13-01T00:00Z",
                           "2024-00-10T00:00Z",
                           "2024-02-30T00:00Z",
                           "2023-02-29T00:00Z",
                           "2024-04-31T00:00Z",
                           "2024-06-00T00:00Z",
                           "2024-06-21T24:00Z",
                           "2024-06-21T12:60Z",
                           "2024-06-21T12:00:60Z",
                           "2024-06-21T12:00:00UTC"}) {
    EXPECT_FALSE(parseIso8601Utc(text).has_value()) << '"' << text << '"';
  }
  EXPECT_TRUE(parseIso8601Utc("2024-02-29T00:00Z").has_value());  // leap day
}

TEST(Iso8601, FormatRoundTrips) {
  EXPECT_EQ(formatIso8601Utc(utc(2024, 6, 21, 3, 4, 5)), "2024-06-21T03:04:05Z");
  const UtcTime t = utc(1999, 12, 31, 23, 59, 1.5);
  EXPECT_EQ(parseIso8601Utc(formatIso8601Utc(t)), t);
}

// --- Published reference values --------------------------------------------

// Meeus example 25.a, 1992 October 13.0 TD. The NOAA spreadsheet uses these
// very formulas (its columns are Meeus's intermediate quantities), so its
// values are Meeus's: apparent longitude 199.90895° (199°54'32"), apparent
// declination -7.78507°, apparent right ascension 198.38083° (13h13m31.4s),
// R = 0.99766 AU. TD - UT was ~59 s in 1992, which NOAA ignores: < 0.0003°.
TEST(SolarPosition, MatchesMeeusExample25a) {
  const SolarPosition p = solarPosition(utc(1992, 10, 13), 0.0, 0.0);
  EXPECT_NEAR(p.declinationDeg, -7.78507, 5e-4);
  EXPECT_NEAR(p.rightAscensionDeg, 198.38083, 1e-3);
  EXPECT_NEAR(p.sunDistanceAu, 0.99766, 1e-5);
  // Example 28.a: equation of time 13m42.7s = 13.712 min (Smart's formula,
  // eq. 28.3, which NOAA uses, agrees to a few tenths of a second).
  EXPECT_NEAR(p.equationOfTimeMin, 13.712, 0.02);
}

// NREL Solar Position Algorithm reference case (Reda & Andreas 2004, "Solar
// position algorithm for solar radiation applications", Solar Energy 76,
// Table A4.1 / A5.1): 2003-10-17 12:30:30 local time (UTC-7), 39.742476°N,
// 105.1786°W: topocentric zenith 50.11162°, azimuth 194.34024°. SPA adds
// parallax (0.0024°) and pressure/temperature-scaled refraction (820 mbar,
// 11 °C); NOAA's standard refraction differs from it by ~0.004° here.
TEST(SolarPosition, MatchesNrelSpaReferenceWithinNoaaAccuracy) {
  const std::optional<UtcTime> t = parseIso8601Utc("2003-10-17T12:30:30-07:00");
  ASSERT_TRUE(t.has_value());
  const SolarPosition p = solarPosition(*t, 39.742476, -105.1786);
  EXPECT_NEAR(p.elevationDeg, 90.0 - 50.11162, 0.02);
  EXPECT_NEAR(p.azimuthDeg, 194.34024, 0.02);
  // Hand-evaluated NOAA spreadsheet values for this instant (see
  // docs/sun-and-sky.md): declination -9.3158°, equation of time 14.647 min,
  // uncorrected elevation 39.8721°, refraction 0.0193°.
  EXPECT_NEAR(p.declinationDeg, -9.3158, 1e-3);
  EXPECT_NEAR(p.equationOfTimeMin, 14.647, 0.005);
  EXPECT_NEAR(p.geometricElevationDeg, 39.8721, 1e-3);
  EXPECT_NEAR(p.refractionDeg, 0.0193, 5e-4);
}

// The equation of time peaks at about +16.4 min around 3 November and bottoms
// at about -14.2 min around 11 February (e.g. the US Naval Observatory and
// NOAA tables; Meeus fig. 28.a).
TEST(SolarPosition, EquationOfTimeExtremesMatchAlmanac) {
  EXPECT_NEAR(solarPosition(utc(2024, 11, 3, 12), 0, 0).equationOfTimeMin, 16.45, 0.1);
  EXPECT_NEAR(solarPosition(utc(2024, 2, 11, 12), 0, 0).equationOfTimeMin, -14.22, 0.1);
  EXPECT_NEAR(solarPosition(utc(2024, 4, 15, 12), 0, 0).equationOfTimeMin, 0.0, 0.3);
}

// Sunrise is when the geometric centre is 0.833° below the horizon (NOAA's
// "HA Sunrise" uses zenith 90.833°). London (51.5074°N, 0.1278°W) on
// 2024-06-21: published sunrise 04:43 BST = 03:43 UTC, sunset 21:21 BST.
TEST(SolarPosition, LondonSolsticeSunriseAndSunsetMatchAlmanacToTheMinute) {
  const double lat = 51.5074, lon = -0.1278;
  auto crossing = [&](UtcTime from, bool rising) {
    double lo = 0, hi = 3600 * 2;  // seconds after `from`
    for (int i = 0; i < 40; ++i) {
      const double mid = 0.5 * (lo + hi);
      const double e = solarPosition(plusSeconds(from, mid), lat, lon).geometricElevationDeg;
      ((e > -0.833) == rising ? hi : lo) = mid;
    }
    return 0.5 * (lo + hi);
  };
  const double sunrise = crossing(utc(2024, 6, 21, 3, 0), true);    // s after 03:00 UTC
  const double sunset = crossing(utc(2024, 6, 21, 19, 30), false);  // s after 19:30 UTC
  EXPECT_GE(sunrise, 42 * 60.0) << "sunrise " << sunrise / 60 << " min after 03:00 UTC";
  EXPECT_LT(sunrise, 44 * 60.0) << "sunrise " << sunrise / 60 << " min after 03:00 UTC";
  EXPECT_GE(sunset, 50 * 60.0) << "sunset " << sunset / 60 << " min after 19:30 UTC";
  EXPECT_LT(sunset, 52 * 60.0) << "sunset " << sunset / 60 << " min after 19:30 UTC";
}

TEST(SolarPosition, EquinoxNoonAtTheEquatorIsOverhead) {
  const UtcTime noon = solarNoonUtc(utc(2024, 3, 20), 0.0);
  const SolarPosition p = solarPosition(noon, 0.0, 0.0);
  EXPECT_NEAR(p.hourAngleDeg, 0.0, 1e-3);
  EXPECT_NEAR(p.elevationDeg, 90.0 - std::abs(p.declinationDeg), 1e-3);
  EXPECT_GT(p.elevationDeg, 89.5);
}

TEST(SolarPosition, SolsticeNoonElevationIsNinetyMinusLatitudePlusObliquity) {
  const double lat = 36.6, lon = -121.9;  // Monterey, California
  const SolarPosition p = solarPosition(solarNoonUtc(utc(2024, 6, 21), lon), lat, lon);
  EXPECT_NEAR(p.declinationDeg, 23.44, 0.01);
  // 90 - 36.6 + 23.44 = 76.84, plus 0.004° of refraction.
  EXPECT_NEAR(p.elevationDeg, 90.0 - lat + 23.44, 0.02);
  EXPECT_NEAR(p.azimuthDeg, 180.0, 0.05);
}

TEST(SolarPosition, SolarNoonIsTwelveMinusLongitudeMinusEquationOfTime) {
  // Greenwich, 3 November: noon at about 11:43:33 UTC.
  const UtcTime noon = solarNoonUtc(utc(2024, 11, 3, 17, 5), 0.0);
  EXPECT_EQ(noon.hour, 11);
  EXPECT_EQ(noon.minute, 43);
  // 90°E: 6 hours earlier; at 179°E noon (12:00 - 11:56 - 16.4 min) rolls
  // back to the previous UTC day.
  const UtcTime east = solarNoonUtc(utc(2024, 11, 3), 90.0);
  EXPECT_EQ(east.hour, 5);
  const UtcTime dateLine = solarNoonUtc(utc(2024, 11, 3), 179.0);
  EXPECT_EQ(dateLine.month, 11);
  EXPECT_EQ(dateLine.day, 2);
  EXPECT_EQ(dateLine.hour, 23);
  EXPECT_NEAR(solarPosition(dateLine, 0, 179.0).hourAngleDeg, 0.0, 1e-3);
}

// --- Conventions -------------------------------------------------------------

TEST(SolarPosition, MorningSunIsInTheEastAndEveningSunInTheWest) {
  const UtcTime noon = solarNoonUtc(utc(2024, 3, 20), 0.0);
  const double noonSeconds = 3600.0 * noon.hour + 60.0 * noon.minute + noon.second;
  const double morning = noonSeconds - 5.5 * 3600, evening = noonSeconds + 5.5 * 3600;
  auto at = [](double seconds) {
    UtcTime t = utc(2024, 3, 20);
    t.hour = static_cast<int>(seconds / 3600);
    t.minute = static_cast<int>((seconds - 3600 * t.hour) / 60);
    t.second = seconds - 3600 * t.hour - 60 * t.minute;
    return t;
  };
  const SolarPosition am = solarPosition(at(morning), 0.0, 0.0);
  const SolarPosition pm = solarPosition(at(evening), 0.0, 0.0);
  EXPECT_NEAR(am.azimuthDeg, 90.0, 0.5);
  EXPECT_NEAR(pm.azimuthDeg, 270.0, 0.5);
  EXPECT_NEAR(am.elevationDeg, 7.5 + am.refractionDeg, 0.2);  // 15°/h * 0.5 h
  EXPECT_LT(am.hourAngleDeg, 0.0);
  EXPECT_GT(pm.hourAngleDeg, 0.0);
  const glm::vec3 dir = sunDirection(am.azimuthDeg, am.elevationDeg);
  EXPECT_GT(dir.x, 0.95f);  // east
}

TEST(SolarPosition, NoonSunIsSouthInTheNorthAndNorthInTheSouth) {
  const UtcTime date = utc(2024, 12, 1);
  const SolarPosition north = solarPosition(solarNoonUtc(date, 10.0), 48.0, 10.0);
  EXPECT_NEAR(north.azimuthDeg, 180.0, 0.05);
  const SolarPosition south = solarPosition(solarNoonUtc(date, 151.2), -60.0, 151.2);
  EXPECT_TRUE(south.azimuthDeg < 0.05 || south.azimuthDeg > 359.95) << south.azimuthDeg;
  EXPECT_GT(sunDirection(south.azimuthDeg, south.elevationDeg).y, 0.5f);
}

TEST(SolarPosition, PolarNightAndPolarDayAtEightyNorth) {
  double highestWinter = -90, lowestSummer = 90;
  for (int minute = 0; minute < 24 * 60; minute += 10) {
    const UtcTime winter = utc(2024, 12, 21, minute / 60, minute % 60);
    const UtcTime summer = utc(2024, 6, 21, minute / 60, minute % 60);
    highestWinter = std::max(highestWinter, solarPosition(winter, 80.0, 15.0).elevationDeg);
    lowestSummer = std::min(lowestSummer, solarPosition(summer, 80.0, 15.0).elevationDeg);
  }
  EXPECT_LT(highestWinter, 0.0);
  EXPECT_NEAR(highestWinter, 90.0 - 80.0 - 23.44, 0.1);
  EXPECT_GT(lowestSummer, 0.0);
}

TEST(SolarPosition, ApparentElevationIsGeometricPlusNoaaRefraction) {
  for (int hour = 0; hour < 24; ++hour) {
    const SolarPosition p = solarPosition(utc(2024, 9, 1, hour, 17), 45.0, 7.0);
    EXPECT_NEAR(p.elevationDeg, p.geometricElevationDeg + p.refractionDeg, 1e-12);
    EXPECT_GE(p.refractionDeg, 0.0);
    EXPECT_LT(p.refractionDeg, 0.6);  // ~0.48° at the horizon, the NOAA maximum
    EXPECT_GE(p.azimuthDeg, 0.0);
    EXPECT_LT(p.azimuthDeg, 360.0);
  }
}

// Refraction near the horizon against the published standard (10 °C,
// 1010 mbar) formulas, evaluated here: Sæmundsson's for the true (geometric)
// altitude h, R = 1.02' cot(h + 10.3/(h + 5.11)) (Sæmundsson 1986, Sky &
// Telescope 72:70), and Bennett's for the apparent altitude a,
// R = 1' cot(a + 7.31/(a + 4.4)) (Bennett 1982, "The Calculation of
// Astronomical Refraction in Marine Navigation", J. Navigation 35:255), both
// as in Meeus, "Astronomical Algorithms", ch. "Atmospheric Refraction".
// True 0° and 2°: 28.98' and 16.93'; apparent 0° and 2°: 34.48' (the
// textbook 34.5' at the horizon) and 18.22'. Bennett's is within 0.07' of
// Garfinkel's tables and Sæmundsson's within 0.1' of Bennett's (Meeus); NOAA's
// fit reads 28.92', 17.02', 34.49' and 18.29'. The 0.12' bound is 7% of the
// 1.45' that 5% more on NOAA's near-horizon constant (1735") adds.
TEST(SolarPosition, RefractionNearTheHorizonMatchesPublishedValues) {
  const double lat = 51.5074, lon = -0.1278;
  const UtcTime from = utc(2024, 6, 21, 3, 0);  // London's sunrise, rising to 13° by 05:00
  const auto at = [&](double elevationDeg, bool apparent) {
    double lo = 0, hi = 7200;  // seconds after `from`
    for (int i = 0; i < 60; ++i) {
      const double mid = 0.5 * (lo + hi);
      const SolarPosition p = solarPosition(plusSeconds(from, mid), lat, lon);
      ((apparent ? p.elevationDeg : p.geometricElevationDeg) < elevationDeg ? lo : hi) = mid;
    }
    return solarPosition(plusSeconds(from, 0.5 * (lo + hi)), lat, lon);
  };
  const auto cotDeg = [](double deg) { return 1.0 / std::tan(deg * std::acos(-1.0) / 180); };
  for (const double h : {0.0, 2.0}) {
    const SolarPosition p = at(h, false);
    ASSERT_NEAR(p.geometricElevationDeg, h, 1e-6);
    const double saemundsson = 1.02 * cotDeg(h + 10.3 / (h + 5.11));
    EXPECT_NEAR(p.refractionDeg * 60, saemundsson, 0.12) << "true altitude " << h << "°";
  }
  for (const double a : {0.0, 2.0}) {
    const SolarPosition p = at(a, true);
    // NOAA's branches meet at -0.575° true, 0° apparent: a wrong constant
    // makes the apparent elevation jump over 0° there.
    EXPECT_NEAR(p.elevationDeg, a, 1e-6) << "the apparent elevation jumps over " << a << "°";
    const double bennett = cotDeg(a + 7.31 / (a + 4.4));
    EXPECT_NEAR(p.refractionDeg * 60, bennett, 0.12) << "apparent altitude " << a << "°";
  }
}

TEST(SunDirection, FollowsTheWorldFrame) {
  auto near = [](const glm::vec3& a, const glm::vec3& b) { return glm::length(a - b) < 1e-6f; };
  EXPECT_TRUE(near(sunDirection(0, 0), {0, 1, 0}));     // north
  EXPECT_TRUE(near(sunDirection(90, 0), {1, 0, 0}));    // east
  EXPECT_TRUE(near(sunDirection(180, 0), {0, -1, 0}));  // south
  EXPECT_TRUE(near(sunDirection(270, 0), {-1, 0, 0}));  // west
  EXPECT_TRUE(near(sunDirection(123, 90), {0, 0, 1}));
  const glm::vec3 d = sunDirection(315, 30);  // north-west, 30° up
  EXPECT_NEAR(glm::length(d), 1.0f, 1e-6f);
  EXPECT_NEAR(d.z, 0.5f, 1e-6f);
  EXPECT_LT(d.x, 0.0f);
  EXPECT_GT(d.y, 0.0f);
}

}  // namespace
}  // namespace aal
