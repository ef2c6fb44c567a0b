"""The lockstep rostests' wait: a condition that another thread or node makes true, with a bound."""
import time


def wait_for(test, condition, what, timeout=10.0):
    """Fails `test` (a unittest.TestCase) unless condition() holds within `timeout` s of wall time."""
    end = time.time() + timeout
    while not condition():
        test.assertLess(time.time(), end, 'no ' + what + ' within %.0f s' % timeout)
        time.sleep(0.02)
