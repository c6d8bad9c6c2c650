#!/usr/bin/env python3
"""One line from `fray-cli metrics SCENE --json` (on stdin): the figures the scale sections compare.

characters, hits (and how many characters received one), penetration samples
(outside intended contacts, as the metrics count them), foot skate: the mean
over characters of their mean per frame, and the largest per frame (cm).

    fray-cli metrics part.frayscene --json -q | bench/metrics_summary.py
"""
import json
import sys

m = json.load(sys.stdin)
cs = m["characters"]
skate = [c["foot_skate_mean_cm"] for c in cs if c["foot_skate_mean_cm"] is not None]
skate_max = max((c["foot_skate_max_cm"] or 0) for c in cs) if cs else 0
hit = sum(1 for c in cs if c["hits_received"] > 0)
print(f"{len(cs)} characters, {m['hits']} hits ({hit} characters hit), {m['penetration_frames']} penetration samples "
      f"({m['cross_group_penetrations']} between groups), foot skate mean {sum(skate) / max(1, len(skate)):.3f} cm, "
      f"max {skate_max:.2f} cm")
