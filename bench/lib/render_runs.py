"""What bench/lib/common.sh render_run leaves in WORK, read back: one render's wall seconds, cache state and the
sums over its --stats frames."""
import json

MiB = 1 << 20


def load(work, name):
    rows = [json.loads(line) for line in open(f"{work}/{name}.jsonl")]
    return {"s": float(open(f"{work}/{name}.s").read()), "cache": open(f"{work}/{name}.cache").read().strip(),
            "frames": len(rows), "working": rows[-1]["working_set_bricks"],
            "uploaded": sum(r["bricks_uploaded"] for r in rows),
            "read": sum(r.get("bytes_read", 0) for r in rows) / MiB,
            "poolFull": rows[-1]["leaves_pool_full"], "solid": rows[-1].get("leaves_solid", 0),
            "converged": rows[-1]["converged"],
            "queries": sum(r.get("occlusion_queries", 0) for r in rows)}
