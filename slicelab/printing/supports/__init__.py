"""Support material under unheld overhangs and mid-air islands.

==========================  =====================================================
``supports.columns``        support masks projected down from what is unheld, and their lines
==========================  =====================================================
"""
