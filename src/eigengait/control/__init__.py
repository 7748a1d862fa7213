"""Controllers: the modal pulse state machine and the balance tracker."""

from eigengait.control.binding import bind_sketch

__all__ = ["bind_sketch"]
