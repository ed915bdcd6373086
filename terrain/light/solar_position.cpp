#include "aperture/terrain/light/solar_position.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "aperture/terrain/units.h"

namespace aal {

namespace {

double sinDeg(double deg) {
  return std::sin(radians(deg));
}
double cosDeg(double deg) {
  return std::cos(radians(deg));
}
double tanDeg(double deg) {
  return std::tan(radians(deg));
}
double wrap(double value, double period) {
  const double r = std::fmod(value, period);
  return r < 0 ? r + period : r;
}

// Reads fixed-width fields left to right; every method fails softly.
class Cursor {
 public:
  explicit Cursor(const std::string& text) : text_(text) {}

  bool atEnd() const { return pos_ == text_.size(); }
  bool peekDigit() const { return pos_ < text_.size() && isDigit(text_[pos_]); }
  bool accept(char c) {
    if (pos_ < text_.size() && text_[pos_] == c) {
      ++pos_;
      return true;
    }
    return false;
  }
  // Exactly `count` decimal digits.
  bool digits(int count, int& value) {
    value = 0;
    for (int i = 0; i < count; ++i) {
      if (!peekDigit()) return false;
      value = 10 * value + (text_[pos_++] - '0');
    }
    return true;
  }
  // One or more digits after a decimal mark, as a fraction in [0, 1).
  bool fraction(double& value) {
    if (!peekDigit()) return false;
    double scale = 0.1;
    value = 0;
    while (peekDigit()) {
      value += scale * (text_[pos_++] - '0');
      scale *= 0.1;
    }
    return true;
  }

 private:
  static bool isDigit(char c) { return c >= '0' && c <= '9'; }
  const std::string& text_;
  size_t pos_ = 0;
};

// Offset designator after the time: "Z", "+hh:mm", "+hhmm", "+hh" (minutes
// east of UTC), or nothing (UTC).
bool parseOffset(Cursor& cursor, int& offsetMinutes) {
  offsetMinutes = 0;
  if (cursor.accept('Z') || cursor.accept('z') || cursor.atEnd()) return true;
  int sign = 0;
  if (cursor.accept('+')) sign = 1;
  if (sign == 0 && cursor.accept('-')) sign = -1;
  if (sign == 0) return false;
  int hours = 0, minutes = 0;
  if (!cursor.digits(2, hours)) return false;
  const bool colon = cursor.accept(':');
  if (colon || cursor.peekDigit()) {
    if (!cursor.digits(2, minutes)) return false;
  }
  if (hours > 23 || minutes > 59) return false;
  offsetMinutes = sign * (60 * hours + minutes);
  return true;
}

bool validDate(int year, int month, int day) {
  const std::chrono::year_month_day ymd{std::chrono::year{year},
                                        std::chrono::month{static_cast<unsigned>(month)},
                                        std::chrono::day{static_cast<unsigned>(day)}};
  return month >= 1 && month <= 12 && day >= 1 && ymd.ok();
}

// Midnight (00:00 UTC) of the date in `time`, plus `seconds` (may be negative
// or more than a day), normalised into a calendar date and time of day.
UtcTime midnightPlusSeconds(const UtcTime& time, double seconds) {
  using namespace std::chrono;
  const sys_days date = year_month_day{year{time.year}, month{static_cast<unsigned>(time.month)},
                                       day{static_cast<unsigned>(time.day)}};
  const double wholeDays = std::floor(seconds / 86400.0);
  double secondOfDay = seconds - 86400.0 * wholeDays;
  const year_month_day ymd{date + days{static_cast<int>(wholeDays)}};
  UtcTime out;
  out.year = static_cast<int>(ymd.year());
  out.month = static_cast<int>(static_cast<unsigned>(ymd.month()));
  out.day = static_cast<int>(static_cast<unsigned>(ymd.day()));
  out.hour = static_cast<int>(secondOfDay / 3600.0);
  secondOfDay -= 3600.0 * out.hour;
  out.minute = static_cast<int>(secondOfDay / 60.0);
  out.second = secondOfDay - 60.0 * out.minute;
  return out;
}

}  // namespace

std::optional<UtcTime> parseIso8601Utc(const std::string& text) {
  Cursor cursor(text);
  UtcTime t;
  if (!cursor.digits(4, t.year) || !cursor.accept('-') || !cursor.digits(2, t.month) ||
      !cursor.accept('-') || !cursor.digits(2, t.day)) {
    return std::nullopt;
  }
  if (!cursor.accept('T') && !cursor.accept('t') && !cursor.accept(' ')) return std::nullopt;
  if (!cursor.digits(2, t.hour) || !cursor.accept(':') || !cursor.digits(2, t.minute)) {
    return std::nullopt;
  }
  if (cursor.accept(':')) {
    int whole = 0;
    if (!cursor.digits(2, whole)) return std::nullopt;
    double fraction = 0;
    if ((cursor.accept('.') || cursor.accept(',')) && !cursor.fraction(fraction)) {
      return std::nullopt;
    }
    t.second = whole + fraction;
  }
  int offsetMinutes = 0;
  if (!parseOffset(cursor, offsetMinutes) || !cursor.atEnd()) return std::nullopt;
  if (!validDate(t.year, t.month, t.day) || t.hour > 23 || t.minute > 59 || t.second >= 60.0) {
    return std::nullopt;
  }
  if (offsetMinutes == 0) return t;
  // Local time minus the offset is UTC.
  return midnightPlusSeconds(t, 3600.0 * t.hour + 60.0 * (t.minute - offsetMinutes) + t.second);
}

std::string formatIso8601Utc(const UtcTime& time) {
  char buffer[64];
  const double whole = std::floor(time.second);
  if (time.second == whole) {
    std::snprintf(buffer, sizeof buffer, "%04d-%02d-%02dT%02d:%02d:%02dZ", time.year, time.month,
                  time.day, time.hour, time.minute, static_cast<int>(whole));
  } else {
    std::snprintf(buffer, sizeof buffer, "%04d-%02d-%02dT%02d:%02d:%06.3fZ", time.year, time.month,
                  time.day, time.hour, time.minute, time.second);
  }
  return buffer;
}

namespace {
std::chrono::sys_days civilDay(const UtcTime& t) {
  return std::chrono::sys_days(std::chrono::year(t.year) / std::chrono::month(unsigned(t.month)) /
                               std::chrono::day(unsigned(t.day)));
}
double secondsOfDay(const UtcTime& t) {
  return t.hour * 3600.0 + t.minute * 60.0 + t.second;
}
}  // namespace

double secondsBetween(const UtcTime& from, const UtcTime& to) {
  const double days = double((civilDay(to) - civilDay(from)).count());
  return days * 86400.0 + (secondsOfDay(to) - secondsOfDay(from));
}

UtcTime addSeconds(const UtcTime& time, double seconds) {
  const double total = secondsOfDay(time) + seconds;
  const double dayShift = std::floor(total / 86400.0);
  double rest = total - dayShift * 86400.0;  // [0, 86400)
  const std::chrono::year_month_day ymd(civilDay(time) + std::chrono::days(int64_t(dayShift)));
  UtcTime t;
  t.year = int(ymd.year());
  t.month = int(unsigned(ymd.month()));
  t.day = int(unsigned(ymd.day()));
  t.hour = std::min(23, int(rest / 3600.0));
  rest -= t.hour * 3600.0;
  t.minute = std::min(59, int(rest / 60.0));
  t.second = std::max(0.0, rest - t.minute * 60.0);
  return t;
}

// Meeus eq. 7.1 with the Gregorian correction B.
double julianDay(const UtcTime& time) {
  int y = time.year, m = time.month;
  if (m <= 2) {
    y -= 1;
    m += 12;
  }
  const double a = std::floor(y / 100.0);
  const double b = 2.0 - a + std::floor(a / 4.0);
  const double dayFraction = (time.hour + (time.minute + time.second / 60.0) / 60.0) / 24.0;
  return std::floor(365.25 * (y + 4716)) + std::floor(30.6001 * (m + 1)) + time.day + dayFraction +
         b - 1524.5;
}

SolarPosition solarPosition(const UtcTime& time, double latitudeDeg, double longitudeDeg) {
  // Julian centuries since J2000.0 (Meeus eq. 25.1).
  const double t = (julianDay(time) - 2451545.0) / 36525.0;

  // Geometric mean longitude and mean anomaly of the sun, eccentricity of the
  // Earth's orbit (Meeus eqs. 25.2-25.4), degrees.
  const double meanLongitude = wrap(280.46646 + t * (36000.76983 + t * 0.0003032), 360.0);
  const double meanAnomaly = 357.52911 + t * (35999.05029 - 0.0001537 * t);
  const double eccentricity = 0.016708634 - t * (0.000042037 + 0.0000001267 * t);

  // Equation of the centre, true longitude and anomaly, radius vector (Meeus
  // ch. 25; NOAA "Sun Eq of Ctr", "Sun True Long", "Sun Rad Vector").
  const double centre = sinDeg(meanAnomaly) * (1.914602 - t * (0.004817 + 0.000014 * t)) +
                        sinDeg(2 * meanAnomaly) * (0.019993 - 0.000101 * t) +
                        sinDeg(3 * meanAnomaly) * 0.000289;
  const double trueLongitude = meanLongitude + centre;
  const double trueAnomaly = meanAnomaly + centre;
  const double distanceAu =
      1.000001018 * (1 - eccentricity * eccentricity) / (1 + eccentricity * cosDeg(trueAnomaly));

  // Apparent longitude (nutation and aberration, Meeus eq. 25.8 and the line
  // after it) and obliquity (Meeus eq. 22.2, corrected as in ch. 25).
  const double omega = 125.04 - 1934.136 * t;
  const double apparentLongitude = trueLongitude - 0.00569 - 0.00478 * sinDeg(omega);
  const double meanObliquity =
      23.0 + (26.0 + (21.448 - t * (46.815 + t * (0.00059 - t * 0.001813))) / 60.0) / 60.0;
  const double obliquity = meanObliquity + 0.00256 * cosDeg(omega);

  // Apparent right ascension and declination (Meeus eqs. 25.6, 25.7).
  const double rightAscension =
      std::atan2(cosDeg(obliquity) * sinDeg(apparentLongitude), cosDeg(apparentLongitude)) /
      kRadiansPerDegree;
  const double declination =
      std::asin(sinDeg(obliquity) * sinDeg(apparentLongitude)) / kRadiansPerDegree;

  // Equation of time, Smart's formula (Meeus eq. 28.3), in minutes of time.
  const double y = tanDeg(obliquity / 2) * tanDeg(obliquity / 2);
  const double eotRad = y * sinDeg(2 * meanLongitude) - 2 * eccentricity * sinDeg(meanAnomaly) +
                        4 * eccentricity * y * sinDeg(meanAnomaly) * cosDeg(2 * meanLongitude) -
                        0.5 * y * y * sinDeg(4 * meanLongitude) -
                        1.25 * eccentricity * eccentricity * sinDeg(2 * meanAnomaly);
  const double equationOfTimeMin = 4.0 * eotRad / kRadiansPerDegree;

  // True solar time and hour angle (NOAA spreadsheet, time zone 0).
  const double minutesUtc = 60.0 * time.hour + time.minute + time.second / 60.0;
  const double trueSolarMin = wrap(minutesUtc + equationOfTimeMin + 4.0 * longitudeDeg, 1440.0);
  const double hourAngle = trueSolarMin / 4.0 - 180.0;

  // Horizontal coordinates. NOAA writes the zenith angle with acos and the
  // azimuth with acos and a branch on the hour angle; the same angles come
  // from the local east/north/up components of the sun's direction with
  // atan2, which stays accurate near the zenith and at the poles.
  const double east = -cosDeg(declination) * sinDeg(hourAngle);
  const double north = sinDeg(declination) * cosDeg(latitudeDeg) -
                       cosDeg(declination) * cosDeg(hourAngle) * sinDeg(latitudeDeg);
  const double up = sinDeg(declination) * sinDeg(latitudeDeg) +
                    cosDeg(declination) * cosDeg(hourAngle) * cosDeg(latitudeDeg);
  const double geometricElevation = std::atan2(up, std::hypot(east, north)) / kRadiansPerDegree;
  const double azimuth = wrap(std::atan2(east, north) / kRadiansPerDegree, 360.0);

  // NOAA atmospheric refraction correction, in arc seconds.
  const double e = geometricElevation;
  const double te = tanDeg(e);
  double refractionArcsec = 0.0;
  if (e > 85.0) {
    refractionArcsec = 0.0;
  } else if (e > 5.0) {
    refractionArcsec = 58.1 / te - 0.07 / (te * te * te) + 0.000086 / std::pow(te, 5);
  } else if (e > -0.575) {
    refractionArcsec = 1735.0 + e * (-518.2 + e * (103.4 + e * (-12.79 + e * 0.711)));
  } else {
    refractionArcsec = -20.772 / te;
  }
  const double refraction = refractionArcsec / 3600.0;

  SolarPosition p;
  p.azimuthDeg = azimuth >= 360.0 ? 0.0 : azimuth;
  p.geometricElevationDeg = geometricElevation;
  p.refractionDeg = refraction;
  p.elevationDeg = std::min(90.0, geometricElevation + refraction);
  p.declinationDeg = declination;
  p.rightAscensionDeg = wrap(rightAscension, 360.0);
  p.equationOfTimeMin = equationOfTimeMin;
  p.hourAngleDeg = hourAngle;
  p.sunDistanceAu = distanceAu;
  return p;
}

UtcTime solarNoonUtc(const UtcTime& day, double longitudeDeg) {
  const UtcTime midnight{day.year, day.month, day.day, 0, 0, 0.0};
  // NOAA: noon = 720 - 4 longitude - EoT minutes after 00:00 UTC. The equation
  // of time changes by < 30 s a day; two refinements make it exact to < 0.1 s.
  double noonMin = 720.0 - 4.0 * longitudeDeg;
  for (int i = 0; i < 2; ++i) {
    const SolarPosition p = solarPosition(midnightPlusSeconds(midnight, 60.0 * noonMin), 0.0, 0.0);
    noonMin = 720.0 - 4.0 * longitudeDeg - p.equationOfTimeMin;
  }
  return midnightPlusSeconds(midnight, 60.0 * noonMin);
}

glm::vec3 sunDirection(double azimuthDeg, double elevationDeg) {
  const double cosElevation = cosDeg(elevationDeg);
  return glm::vec3(static_cast<float>(sinDeg(azimuthDeg) * cosElevation),
                   static_cast<float>(cosDeg(azimuthDeg) * cosElevation),
                   static_cast<float>(sinDeg(elevationDeg)));
}

}  // namespace aal
