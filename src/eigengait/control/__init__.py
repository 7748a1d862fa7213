"""Controllers: the modal pulse state machine and the balance tracker."""
