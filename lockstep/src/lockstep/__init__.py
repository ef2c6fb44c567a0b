"""The participant's side of the simulator's lockstep for rospy nodes (see participant.h)."""
from lockstep.participant import Participant  # noqa: F401
from lockstep.script_clock import ScriptClock  # noqa: F401
