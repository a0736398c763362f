"""Machine-written by derivations/poincare_jets.py; do not edit."""
