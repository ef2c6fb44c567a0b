"""What a run's log says about lockstep: the steps that waited for a node past the wall-clock
timeout (lockstep/timeout). Such a run went on without that node's input for a step, so it may not
repeat: its figures are not comparable with another run's."""
import re

# bullet_sim: "bullet_sim: lockstep: the step at 0.150 s waited 10 s of wall time for the
# acknowledgement of /exploration; going on without it"; a participant: "/exploration: lockstep step
# at 0.150 s waited 10 s of wall time for /topological_map: 4 of 5; going on without it".
STALL = re.compile(r'(\S+): lockstep:? (?:the )?step at ([\d.]+) s waited ([\d.]+) s of wall time for (.+?); ')


def stalls(lines):
    """The stalls in `lines` (a log's lines): (node, sim time of the step (s), what it waited for)."""
    out = []
    for line in lines:
        m = STALL.search(line)
        if m:
            out.append((m.group(1), float(m.group(2)), m.group(4)))
    return out


def stalls_in(path):
    """stalls() of the log file at `path`; none if it cannot be read."""
    try:
        with open(path, errors='replace') as f:
            return stalls(f)
    except OSError:
        return []
