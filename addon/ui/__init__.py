# SPDX-License-Identifier: GPL-3.0-or-later
"""Every operator, menu and panel of the extension."""
