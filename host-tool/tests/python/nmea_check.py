"""Parses the NMEA 0183 lines `protolink nmea` wrote, with pynmea2, for host-tool/tests/all/nmea.rs.

Input: a file of lines `SECONDS<TAB>SENTENCE` (the host time the test received the sentence).
Output: one JSON object per sentence on stdout, with the fields in the units each sentence
defines, as pynmea2 read them. Every checksum is checked: pynmea2 parses $GPRMC, $GPGGA and
$PGRMZ as typed sentences with `check=True`; it has no type for $POV (a two-letter proprietary
sender) nor $LXWP0, so for those pynmea2's own checksum function is compared with the `*HH` and
the fields are split here. Any bad or unparsed sentence is an error: exit status 1.
"""

import json
import sys

import pynmea2


def num(text):
    return float(text) if text != "" else None


def untyped(sentence):
    """$POV and $LXWP0: checksum by pynmea2, fields split here."""
    body, _, given = sentence[1:].partition("*")
    if len(given) != 2 or int(given, 16) != pynmea2.NMEASentence.checksum(body):
        raise ValueError("bad checksum: " + sentence)
    fields = body.split(",")
    if fields[0] == "POV":
        pairs = dict(zip(fields[1::2], (float(v) for v in fields[2::2])))
        return {"type": "POV", **pairs}
    if fields[0] == "LXWP0" and len(fields) == 13:
        return {
            "type": "LXWP0",
            "logger": fields[1],
            "tas_kmh": num(fields[2]),
            "altitude_m": num(fields[3]),
            "vario_mps": [num(v) for v in fields[4:10]],
            "heading_deg": num(fields[10]),
            "wind_from_deg": num(fields[11]),
            "wind_kmh": num(fields[12]),
        }
    raise ValueError("unknown sentence: " + sentence)


def typed(sentence):
    m = pynmea2.parse(sentence, check=True)
    if isinstance(m, pynmea2.types.talker.RMC):
        valid = m.status == "A"
        return {
            "type": "RMC",
            "status": m.status,
            "lat": m.latitude if valid else None,
            "lon": m.longitude if valid else None,
            "speed_kt": m.spd_over_grnd,
            "track_deg": m.true_course,
            "date": m.datestamp.isoformat() if m.datestamp else None,
        }
    if isinstance(m, pynmea2.types.talker.GGA):
        fix = m.gps_qual
        return {
            "type": "GGA",
            "quality": fix,
            "lat": m.latitude if fix else None,
            "lon": m.longitude if fix else None,
            "satellites": int(m.num_sats) if m.num_sats else None,
            "altitude": m.altitude,
            "altitude_units": m.altitude_units,
        }
    if isinstance(m, pynmea2.types.proprietary.grm.GRMZ):
        return {
            "type": "PGRMZ",
            "altitude": float(m.altitude) if m.altitude not in (None, "") else None,
            "unit": m.altitude_unit,
        }
    raise ValueError("unexpected sentence type: " + sentence)


def main(path):
    bad = 0
    with open(path, encoding="ascii") as f:
        for line in f:
            t, _, sentence = line.rstrip("\r\n").partition("\t")
            try:
                if len(sentence) + 2 > 82:
                    raise ValueError("longer than 82 characters: " + sentence)
                if sentence.startswith(("$POV,", "$LXWP0,")):
                    out = untyped(sentence)
                else:
                    out = typed(sentence)
            except Exception as e:  # every failure is reported, then the exit status says so
                print("error: %s" % e, file=sys.stderr)
                bad += 1
                continue
            out["t"] = float(t)
            print(json.dumps(out))
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main(sys.argv[1])
